"""MkDocs hook: the CLI reference and the campaign-file keys, generated from the code at build time.

A page holding `<!-- rockcal:cli -->` gets every `rockcal` command with its arguments and
options, read from the typer app (`rockcal.cli.app`); a page holding
`<!-- rockcal:campaign-keys -->` gets every section and key of the campaign file, read from the
pydantic models of `rockcal.campaign.input.config` and `rockcal.campaign.input.targets`. So neither can
drift from the code.
"""

from __future__ import annotations

import html
import inspect
import types
import typing
from pathlib import Path

CLI_MARK = "<!-- rockcal:cli -->"
KEYS_MARK = "<!-- rockcal:campaign-keys -->"


# -- CLI -------------------------------------------------------------------------------------

def _cell(text) -> str:
    """Text for a markdown table cell, its first letter a capital."""
    text = html.escape(" ".join(str(text).split()), quote=False).replace("|", "\\|")
    return text[:1].upper() + text[1:]


def _command_tree():
    """The click command behind the typer app, with every subcommand registered."""
    import typer.main

    from rockcal.cli import app as cli

    if not cli.app.registered_commands and not cli.app.registered_groups:
        cli._register()
    return typer.main.get_command(cli.app)


def _escape_outside_code(line: str) -> str:
    """`<` and `>` outside code spans, escaped (help texts say `runs/<rock name>`)."""
    parts = line.split("`")
    return "`".join(html.escape(p, quote=False) if i % 2 == 0 else p for i, p in enumerate(parts))


def cli_reference() -> str:
    """Every command's usage, arguments and options, by typer's own Markdown generator."""
    import typer
    import typer.cli

    root = _command_tree()
    text = typer.cli.get_docs_for_click(obj=root, ctx=typer.Context(root), name="rockcal", title="rockcal")
    lines, fenced = [], False
    for line in text.strip().splitlines()[1:]:  # the page has its own title
        if line.startswith("```"):
            fenced = not fenced
        lines.append(line if fenced or line.startswith("```") else _escape_outside_code(line))
    return "\n".join(lines)


# -- campaign file -------------------------------------------------------------------------------

SIMPLE = {float: "number", int: "integer", str: "text", bool: "true / false", Path: "file path"}


def _type_name(annotation) -> str:
    """A field's type in the words of a TOML file."""
    origin, args = typing.get_origin(annotation), typing.get_args(annotation)
    if annotation in SIMPLE:
        return SIMPLE[annotation]
    if origin is typing.Literal:
        return " or ".join(f'`"{a}"`' for a in args)
    if origin in (typing.Union, types.UnionType):
        kept = [a for a in args if a is not type(None)]
        return " or ".join(_type_name(a) for a in kept)
    if origin is tuple:
        return "[" + ", ".join(_type_name(a) for a in args) + "]"
    if origin is list:
        return f"list of {_type_name(args[0])}"
    if origin is dict:
        return f"{{ name = {_type_name(args[1])}, ... }}"
    return getattr(annotation, "__name__", str(annotation))


def _limits(field) -> str:
    import annotated_types as at

    words = []
    for m in field.metadata:
        for cls, attr, sign in ((at.Gt, "gt", ">"), (at.Ge, "ge", "≥"), (at.Lt, "lt", "<"), (at.Le, "le", "≤")):
            if isinstance(m, cls):
                words.append(f"{sign} {getattr(m, attr)}")
    return ", ".join(words)


def _default(field) -> str:
    if field.is_required():
        return "**required**"
    value = field.get_default(call_default_factory=True)
    if value is None:
        return "–"
    if isinstance(value, str):
        return f'`"{value}"`'
    if isinstance(value, bool):
        return f"`{str(value).lower()}`"
    if isinstance(value, (list, tuple)):
        return "`[" + ", ".join(f'"{v}"' if isinstance(v, str) else str(v) for v in value) + "]`"
    if isinstance(value, dict):
        return "`{}`" if not value else f"`{value}`"
    return f"`{value}`"


def _section_doc(table: str, model, optional: bool, required: bool) -> list[str]:
    doc = inspect.cleandoc(model.__doc__ or "")
    if "Usage docs:" in doc or doc.startswith("!!! abstract"):  # pydantic's own docstring
        doc = ""
    presence = "required" if required else ("optional" if optional else "optional, with defaults")
    lines = [f"### `[{table}]`", "", f"*{presence}.* {' '.join(doc.split())}".rstrip(), ""]
    lines += ["| key | type | default | limits | what |", "|---|---|---|---|---|"]
    for name, field in model.model_fields.items():
        lines.append(f"| `{name}` | {_type_name(field.annotation)} | {_default(field)} | "
                     f"{_cell(_limits(field))} | {_cell(field.description or '')} |")
    return lines + [""]


def _model_of(annotation):
    from pydantic import BaseModel

    for a in (annotation, *typing.get_args(annotation)):
        if isinstance(a, type) and issubclass(a, BaseModel):
            return a
    return None


def campaign_keys() -> str:
    from rockcal.campaign.input.config import Campaign
    from rockcal.labtests.lab_values import values_model
    from rockcal.labtests.registry import LAB_TESTS, PRIMARY_TEST

    lines = []
    for name, field in Campaign.model_fields.items():
        model = _model_of(field.annotation)
        optional = type(None) in typing.get_args(field.annotation)
        if name == "targets":  # a section per lab test of the registry, the primary one required
            for test in LAB_TESTS.values():
                lines += _section_doc(f"targets.{test.name}", values_model(test), test.name != PRIMARY_TEST,
                                      test.name == PRIMARY_TEST)
        else:
            lines += _section_doc(name, model, optional, field.is_required())
    return "\n".join(lines)


# -- the hook ------------------------------------------------------------------------------------

def on_page_markdown(markdown: str, **kwargs) -> str:
    if CLI_MARK in markdown:
        markdown = markdown.replace(CLI_MARK, cli_reference())
    if KEYS_MARK in markdown:
        markdown = markdown.replace(KEYS_MARK, campaign_keys())
    return markdown

"""Entry point of the `rockcal` command; every user mistake ends as one line on stderr and exit 2."""

import os
import sys
from typing import Optional

import typer
from typer.core import TyperGroup

from rockcal.version import __version__
from rockcal.specimens.grain_limit import DEFAULT_MAX_GRAINS, ENV, FLAG
from rockcal.errors import InputError


# the commands in the order a user meets them (typer's own: the commands, then the groups)
COMMANDS = ("calibrate", "simulate", "export", "report", "sensitivity", "kic", "export-specimen")


class _InOrder(TyperGroup):
    def list_commands(self, ctx) -> list[str]:
        order = {name: k for k, name in enumerate(COMMANDS)}
        return sorted(super().list_commands(ctx), key=lambda name: order.get(name, len(COMMANDS)))


# plain help (click's): no `<bool>` beside a flag, and it fits 80 columns
app = typer.Typer(cls=_InOrder, add_completion=False, no_args_is_help=True, pretty_exceptions_enable=False,
                  rich_markup_mode=None, help="Calibrate bonded-particle DEM micro-parameters of rock from lab tests.")


def _show_version(shown: bool) -> None:
    if shown:
        typer.echo(f"rockcal {__version__}")
        raise typer.Exit()


@app.callback()
def _options(max_grains: Optional[int] = typer.Option(
        None, FLAG, min=1, help=f"Make specimens of up to this many grains (default {DEFAULT_MAX_GRAINS:,}, "
                                f"or ${ENV}); a larger one is refused before its genesis."),
        version: bool = typer.Option(False, "--version", is_eager=True, callback=_show_version,
                                     help="Show rockcal's version (it keys every stored run) and exit.")) -> None:
    """Calibrate bonded-particle DEM micro-parameters of rock from lab tests."""
    if max_grains is not None:
        os.environ[ENV] = str(max_grains)  # seen by the pool's and a local cluster's workers too


def _register() -> None:
    """Add the commands to `app` for the lab tests registered now, once: a process may run
    `main` many times (a notebook, the tests), and commands added again at each call would slow
    every later call."""
    global _registered_for
    from rockcal.labtests.registry import LAB_TESTS

    if app.registered_commands and tuple(LAB_TESTS) == _registered_for:
        return
    from rockcal.cli import calibrate, export, kic, sensitivity, simulate

    app.registered_groups.clear()
    app.registered_commands.clear()
    app.command("calibrate")(calibrate.calibrate)
    app.add_typer(simulate.build_app(), name="simulate")
    app.command("export")(export.export)
    app.command("report")(calibrate.report)
    app.add_typer(sensitivity.app, name="sensitivity")
    app.command("kic")(kic.kic)
    app.command("export-specimen")(export.export_specimen)
    _registered_for = tuple(LAB_TESTS)


_registered_for: tuple[str, ...] = ()  # the lab tests `simulate`'s commands were made for


def _fail(message: str) -> None:
    print("rockcal: error: " + " ".join(message.split()), file=sys.stderr)
    sys.exit(2)


def _field_of(exc) -> str:
    """The option or argument a command-line mistake is about ("arguments": none in particular)."""
    param = getattr(exc, "param", None)
    if param is not None:
        return max(param.opts, key=len) if param.opts else param.human_readable_name
    return getattr(exc, "option_name", None) or "arguments"


def main() -> None:
    _register()
    try:
        code = app(standalone_mode=False)
    except InputError as exc:
        _fail(str(exc))
    except typer.TyperException as exc:
        if type(exc).__name__ == "NoArgsIsHelpError":  # a bare group: show its help
            print(exc.ctx.get_help())
            sys.exit(0)
        _fail(f"{_field_of(exc)}: {getattr(exc, 'message', None) or exc.format_message()}")
    except typer.Abort:
        _interrupted()
    if code == INTERRUPTED:  # typer's answer to Ctrl-C (KeyboardInterrupt), said in no words
        _interrupted()
    sys.exit(code if isinstance(code, int) else 0)


INTERRUPTED = 130  # the exit status of a command stopped by Ctrl-C (128 + SIGINT)


def _interrupted() -> None:
    print("rockcal: interrupted", file=sys.stderr)
    sys.exit(INTERRUPTED)

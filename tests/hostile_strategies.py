"""Hypothesis strategies of hostile input to the `rockcal` command (`test_hostile_input.py`).

Campaign files: a valid small campaign (the models' defaults, made small), then one to three
mutations at places found by walking the campaign's pydantic models (`Campaign.model_fields`,
nested; [targets] has a section per test of the lab-test registry, each its `values_model`):
a field set to a value chosen by its annotation and its constraints (`Gt`, `Le`, `MaxLen`: the
bound itself and its neighbours), a wrong type, an extreme number, odd text; a key or a section
deleted, emptied (`[targets.direct_tension]` with nothing in it) or replaced by a scalar; an
unknown key; a list with repeats. Then, now and then, the text itself is broken (truncated, a
byte inserted, not UTF-8, nested 100 000 deep, larger than rockcal reads).

Argument lists: from the option tables of the built click command (`typer.main.get_command`),
each option given a value by its type (int, float, str, Path, choice, flag, repeated).
"""

from __future__ import annotations

import copy
import datetime
import enum
import math
import pathlib
import reprlib
import tempfile
import types
import typing
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import annotated_types as at
from hypothesis import strategies as st
from hypothesis.configuration import set_hypothesis_home_dir
from pydantic import BaseModel

from rockcal.campaign.input.config import NAMES, SEARCHED_GENESIS, Campaign
from rockcal.campaign.input.targets import Targets
from rockcal.labtests.lab_values import values_model
from rockcal.labtests.registry import LAB_TESTS, PRIMARY_TEST
from rockcal.materials import DEFAULT_MATERIAL, MATERIALS

# Hypothesis keeps caches (and, were there one, its example database) in .hypothesis under the
# cwd: here, outside the repository, set before any strategy is built
set_hypothesis_home_dir(Path(tempfile.gettempdir()) / "rockcal-hypothesis")

# ---------------------------------------------------------------------------------------------
# values every field meets

FLOAT_EXTREMES = [0.0, -0.0, -1.0, math.nan, math.inf, -math.inf, 1e300, -1e300, 5e-324, 1e-300,
                  1.7976931348623157e308, 0.5, 1.0]
INT_EXTREMES = [0, -1, 1, 2, 2**31, 2**53 + 1, 2**63 - 1, -(2**63), 2**63, 10**30, -(10**30)]
ODD_TEXT = ["", " ", "\t", "a\nb", "\x00", "\x1b[31mred", "\u202eevil", "名前", "🪨" * 10, "é",
            "\ufeff", "\u200b", "a" * 201, "x" * 100_000, "../..", ".", "..", "runs", "CON", "a/b",
            "\\", "'", '"', "nan", "inf", "1e300", "-1"]
WRONG_TYPES = ["", "1", "abc", True, False, [], [1], [[]], {}, {"a": 1}, datetime.date(2024, 1, 1),
               datetime.datetime(2024, 1, 1, 12, 0), datetime.time(12, 0)]


def _one_of_list(values: list) -> st.SearchStrategy:
    return st.sampled_from(values)


numbers = st.one_of(_one_of_list(FLOAT_EXTREMES), _one_of_list(INT_EXTREMES),
                    st.floats(), st.integers())
wrong_types = _one_of_list(WRONG_TYPES)
odd_text = st.one_of(_one_of_list(ODD_TEXT),
                     st.text(st.characters(exclude_categories=("Cs",)), max_size=30))


def _bounds_of(info) -> list:
    """The numbers at and beside a field's constraints (gt=0: 0, the largest float below 0
    and the smallest above)."""
    found = []
    for m in getattr(info, "metadata", ()) or ():
        for attr in ("gt", "ge", "lt", "le"):
            bound = getattr(m, attr, None)
            if isinstance(bound, (int, float)) and not isinstance(bound, bool):
                found += [bound, math.nextafter(bound, -math.inf), math.nextafter(bound, math.inf)]
                if isinstance(bound, int):
                    found += [bound - 1, bound + 1]
        for attr in ("min_length", "max_length"):
            length = getattr(m, attr, None)
            if isinstance(length, int):
                found += ["a" * max(length - 1, 0), "a" * length, "a" * (length + 1)]
    return found


def _constraint(info, kind) -> Any:
    for m in getattr(info, "metadata", ()) or ():
        if isinstance(m, kind):
            return m
    return None


def _in_range_floats(info) -> st.SearchStrategy:
    """Valid-looking numbers in the field's range (so that a mutation reaches past pydantic)."""
    lo = _constraint(info, at.Gt) or _constraint(info, at.Ge)
    hi = _constraint(info, at.Lt) or _constraint(info, at.Le)
    low = getattr(lo, "gt", getattr(lo, "ge", None)) if lo else None
    high = getattr(hi, "lt", getattr(hi, "le", None)) if hi else None
    return st.floats(min_value=low, max_value=high, allow_nan=False, allow_infinity=False,
                     exclude_min=isinstance(lo, at.Gt), exclude_max=isinstance(hi, at.Lt))


# names a campaign's tables are keyed by: the parameters of every material, the searched genesis
# settings, the tests of the registry and each test's responses
KNOWN_KEYS = sorted({*NAMES, *SEARCHED_GENESIS, *LAB_TESTS,
                     *(r for t in LAB_TESTS.values() for r in t.targets)})
keys = st.one_of(_one_of_list(KNOWN_KEYS), odd_text)


def hostile(annotation, info=None) -> st.SearchStrategy:
    """Values for a field of this annotation: wrong types, extremes, its bounds and their
    neighbours, odd text, containers with odd contents."""
    origin, args = typing.get_origin(annotation), typing.get_args(annotation)
    if origin in (typing.Union, types.UnionType):
        members = [a for a in args if a is not type(None)]
        return st.one_of(*(hostile(a, info) for a in members))
    near = [_one_of_list(_bounds_of(info))] if _bounds_of(info) else []
    if annotation is bool:
        return st.one_of(st.booleans(), wrong_types, numbers)
    if annotation in (int, float):
        valid = [_in_range_floats(info)] if annotation is float else []
        return st.one_of(*near, numbers, *valid, wrong_types, odd_text)
    if annotation is str:
        return st.one_of(*near, odd_text, wrong_types, numbers, _one_of_list(list(MATERIALS)))
    if origin is typing.Literal:
        choices = [str(a) for a in args]
        return st.one_of(_one_of_list(choices), _one_of_list([c.upper() for c in choices] + [c + " " for c in choices]),
                         odd_text, wrong_types, numbers)
    if annotation is pathlib.Path:
        return st.one_of(_one_of_list(CURVE_PATHS), odd_text, wrong_types)
    if origin is dict:
        return st.one_of(st.dictionaries(keys, hostile(args[1]), max_size=5), wrong_types, numbers)
    if origin in (list, tuple):
        element = hostile(args[0]) if args else numbers
        return st.one_of(st.lists(element, max_size=6), st.lists(element, min_size=1, max_size=3).map(lambda v: v + v),
                         wrong_types, numbers)
    return st.one_of(wrong_types, numbers, odd_text)


# ---------------------------------------------------------------------------------------------
# the campaign's fields, from its models

@dataclass(frozen=True)
class Leaf:
    path: tuple[str, ...]
    annotation: Any
    info: Any


def _model_of(annotation) -> type[BaseModel] | None:
    candidates = [annotation, *typing.get_args(annotation)]
    return next((a for a in candidates if isinstance(a, type) and issubclass(a, BaseModel)), None)


def _walk(model: type[BaseModel], prefix: tuple[str, ...] = ()):
    """(tables, leaves) of a model: a table per nested model, [targets.<test>] for each test."""
    tables, leaves = [], []
    for name, info in model.model_fields.items():
        key = info.alias or name
        sub = _model_of(info.annotation)
        if sub is Targets:
            tables.append(prefix + (key,))
            for test in LAB_TESTS.values():
                t, lv = _walk(values_model(test), prefix + (key, test.name))
                tables += [prefix + (key, test.name), *t]
                leaves += lv
        elif sub is not None:
            t, lv = _walk(sub, prefix + (key,))
            tables += [prefix + (key,), *t]
            leaves += lv
        else:
            leaves.append(Leaf(prefix + (key,), info.annotation, info))
    return tables, leaves


TABLES, LEAVES = _walk(Campaign)
LEAF_PATHS = [".".join(leaf.path) for leaf in LEAVES]


def _defaults(model: type[BaseModel]) -> dict:
    """A section at its model's defaults, as a campaign file would write them."""
    return model().model_dump(mode="json", exclude_none=True, exclude_defaults=False)


# The valid small campaign every case starts from: each section at its model's defaults, made
# small (a 5 x 10 mm UCS specimen, the fewest runs the models allow) so that a dry run plans in
# a tenth of a second. [validation] is left out: giving it names the tests checked.
SMALL = {
    "rock": {"name": "tiny"},
    "targets": {PRIMARY_TEST: {"E_GPa": 41.5, "nu": 0.23, "ucs_MPa": 138.8}},
    "specimen": {"width_mm": 5.0, "height_mm": 10.0, "beam_length_mm": 22.0, "beam_height_mm": 5.0,
                 "notch_mm": 1.8, "notch_width_mm": 0.2, "span_mm": 16.0, "disk_diameter_mm": 5.0},
    "search": {"bounds": {"E_c": [20.0, 30.0], "sigma_c": [30.0, 50.0]}},
    "surrogate": {"samples": 4, "checks": 1},
    "optimizer": {"ants": 2, "iterations": 1},
    "acceptance": {"max_dem_runs": 10},
    "uncertainty": {"enabled": False, "draws": 10, "packings": 1},
}
# a valid section of each other lab test, and of [sensitivity]: some of them join a case's base
OPTIONAL = {
    ("targets", "bending"): {"K_IC_MPa_sqrt_m": 1.0},
    ("targets", "brazilian"): {"sigma_t_MPa": 8.0},
    ("targets", "biaxial"): {"confinement_mpa": [0.0, 5.0], "sigma1_MPa": [140.0, 170.0]},
    ("targets", "direct_tension"): {"sigma_t_direct_MPa": 6.9},
    ("sensitivity",): {"array": "L4(2^3)", "levels": {"E_c": [20.0, 30.0], "sigma_c": [30.0, 50.0]}},
}
CHECK_ONLY = ("bending", "direct_tension")  # given, they are named in [validation] tests


def _merge(base: dict, over: dict) -> dict:
    out = copy.deepcopy(base)
    for k, v in over.items():
        out[k] = _merge(out[k], v) if isinstance(v, dict) and isinstance(out.get(k), dict) else copy.deepcopy(v)
    return out


def base_campaign(optional: tuple = ()) -> dict:
    """The small valid campaign, with the OPTIONAL sections named."""
    doc = {}
    for name, info in Campaign.model_fields.items():
        sub = _model_of(info.annotation)
        if sub is not None and sub is not Targets and info.default is not None and name != "validation":
            doc[name] = _defaults(sub)
    doc = _merge(doc, SMALL)
    for path in optional:
        set_path(doc, path, copy.deepcopy(OPTIONAL[path]))
    given = [p[1] for p in optional if p[0] == "targets"]
    doc["validation"] = {"tests": [t for t in given if t in CHECK_ONLY]}
    return doc


def set_path(doc: dict, path: tuple, value) -> None:
    node = doc
    for key in path[:-1]:
        if not isinstance(node.get(key), dict):
            node[key] = {}
        node = node[key]
    node[path[-1]] = value


def existing_paths(doc, prefix=()) -> list[tuple]:
    found = []
    for k, v in doc.items():
        found.append(prefix + (k,))
        if isinstance(v, dict):
            found += existing_paths(v, prefix + (k,))
    return found


def _list_paths(doc, prefix=()) -> list[tuple]:
    return [p for p in existing_paths(doc) if isinstance(_get(doc, p), list) and _get(doc, p)]


def _get(doc, path):
    for k in path:
        doc = doc[k]
    return doc


# ---------------------------------------------------------------------------------------------
# TOML text (rockcal reads TOML; nothing here writes it)

_BARE = set("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_-")


def _string(s: str) -> str:
    out = []
    for ch in s:
        if ch == '"':
            out.append('\\"')
        elif ch == "\\":
            out.append("\\\\")
        elif ord(ch) < 0x20 or ord(ch) == 0x7F:
            out.append(f"\\u{ord(ch):04x}")
        else:
            out.append(ch)
    return '"' + "".join(out) + '"'


def _key(k: str) -> str:
    return k if k and set(k) <= _BARE else _string(k)


def _value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, str):
        return _string(v)
    if isinstance(v, (datetime.date, datetime.time)):
        return v.isoformat()
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join(f"{_key(k)} = {_value(x)}" for k, x in v.items()) + "}"
    raise TypeError(type(v))


def toml_dumps(doc: dict) -> str:
    """TOML of a document: scalars and arrays first, then each table under its header."""
    lines: list[str] = []

    def table(node: dict, path: tuple):
        scalars = {k: v for k, v in node.items() if not isinstance(v, dict)}
        tables = {k: v for k, v in node.items() if isinstance(v, dict)}
        if path and (scalars or not tables):
            lines.append("[" + ".".join(_key(k) for k in path) + "]")
        lines.extend(f"{_key(k)} = {_value(v)}" for k, v in scalars.items())
        for k, v in tables.items():
            table(v, path + (k,))

    table(doc, ())
    return "\n".join(lines) + "\n"


# ---------------------------------------------------------------------------------------------
# campaign cases

CURVE = "curve.csv"  # a measured curve beside the campaign file
CURVE_PATHS = [CURVE, "missing.csv", ".", "", "/dev/zero", "/dev/null", "sub/", "a" * 300 + ".csv",
               "/proc/self/mem"]
VALID_CURVE = "strain,stress_MPa\n0,0\n0.001,40\n0.002,80\n0.003,120\n0.0035,130\n0.004,100\n"


@st.composite
def curve_files(draw) -> bytes:
    """The measured curve's file: valid, or broken."""
    kind = draw(st.sampled_from(["valid", "rows", "template"]))
    if kind == "valid":
        return VALID_CURVE.encode()
    if kind == "template":
        return draw(st.sampled_from([b"", b"\xff\xfe\x00", b"1,2\n", b"0,0\n0.002,1\n0.001,2\n", b"a,b\nc,d\ne,f\n",
                                     b"0;0\n1;1\n2;2\n", b"0,0,0\n1,1,1\n2,2,2\n", b"0\n1\n2\n", b"\x00" * 100,
                                     ("0,0\n" + "".join(f"{i * 1e-6},{i}\n" for i in range(1, 20_000))).encode()]))
    rows = draw(st.lists(st.tuples(numbers, numbers), max_size=12))
    return "".join(f"{_value(a)},{_value(b)}\n" for a, b in rows).encode()


def _deep(kind: str, depth: int) -> str:
    if kind == "array":
        return "x = " + "[" * depth + "]" * depth + "\n"
    if kind == "inline":
        return "x = " + "{a = " * depth + "1" + "}" * depth + "\n"
    return ".".join(["a"] * depth) + " = 1\n"  # dotted keys: a table depth deep


MAX_READ = 16 * 2**20  # rockcal.user_files.MAX_BYTES


@dataclass
class CampaignCase:
    """A campaign file's bytes and the files beside it; `size` pads it (sparse) to that size."""

    text: bytes
    files: dict = field(default_factory=dict)
    size: int | None = None
    mutations: list = field(default_factory=list)

    def __repr__(self) -> str:
        text = self.text.decode("utf-8", "backslashreplace")
        if len(text) > 1500:
            text = text[:700] + f"\n... ({len(text)} characters) ...\n" + text[-700:]
        files = {k: (v[:200] + b"..." if len(v) > 200 else v) for k, v in self.files.items()}
        short = reprlib.Repr()
        short.maxstring = short.maxother = 100
        return (f"CampaignCase(mutations={short.repr(self.mutations)}, size={self.size}, files={files!r}, "
                f"text=\n{text}\n)")

    def _repr_pretty_(self, p, cycle) -> None:  # Hypothesis prints a failing case by this
        p.text(repr(self))


MUTATIONS = ["set", "delete", "empty_table", "unknown_key", "not_a_table", "repeat_list"]
RAW = ["none"] * 6 + ["truncate", "insert", "bom", "duplicate_header", "not_utf8", "nul", "crlf",
                      "empty", "deep", "larger_than_read"]


@st.composite
def campaign_cases(draw) -> CampaignCase:
    optional = draw(st.lists(st.sampled_from(list(OPTIONAL)), unique=True, max_size=len(OPTIONAL)))
    doc = base_campaign(tuple(optional))
    done = []
    for _ in range(draw(st.integers(1, 3))):
        op = draw(st.sampled_from(MUTATIONS))
        if op == "set":
            leaf = draw(st.sampled_from(LEAVES))
            value = draw(hostile(leaf.annotation, leaf.info))
            set_path(doc, leaf.path, value)
            done.append((op, ".".join(leaf.path), value if not isinstance(value, str) or len(value) < 80
                         else value[:40] + f"...({len(value)})"))
        elif op == "delete":
            path = draw(st.sampled_from(existing_paths(doc)))
            parent = _get(doc, path[:-1])
            del parent[path[-1]]
            done.append((op, ".".join(path)))
        elif op == "empty_table":
            path = draw(st.sampled_from(TABLES))
            set_path(doc, path, {})
            done.append((op, ".".join(path)))
        elif op == "unknown_key":
            path = draw(st.sampled_from([(), *TABLES]))
            key = draw(keys)
            value = draw(st.one_of(numbers, odd_text, wrong_types))
            if path:
                set_path(doc, path + (key,), value)
            else:
                doc[key] = value
            done.append((op, ".".join(path + (key,)), value))
        elif op == "not_a_table":
            path = draw(st.sampled_from(TABLES))
            value = draw(st.one_of(numbers, odd_text, st.sampled_from([[], [{}], [{"a": 1}, {"b": 2}], [1, 2]])))
            set_path(doc, path, value)
            done.append((op, ".".join(path), value))
        else:  # a list with its values repeated
            lists = _list_paths(doc)
            if lists:
                path = draw(st.sampled_from(lists))
                old = _get(doc, path)
                set_path(doc, path, old + old[: draw(st.integers(1, len(old)))])
                done.append((op, ".".join(path)))
    data = toml_dumps(doc).encode()
    raw = draw(st.sampled_from(RAW))
    size = None
    if raw == "truncate":
        data = data[: draw(st.integers(0, len(data)))]
    elif raw == "insert":
        at_ = draw(st.integers(0, len(data)))
        data = data[:at_] + draw(st.binary(min_size=1, max_size=4)) + data[at_:]
    elif raw == "bom":
        data = "\ufeff".encode() + data
    elif raw == "duplicate_header":
        data = data + b"[rock]\nname = \"again\"\n"
    elif raw == "not_utf8":
        data = data + b"# \xff\xfe\n"
    elif raw == "nul":
        data = data + b"\x00"
    elif raw == "crlf":
        data = data.replace(b"\n", b"\r\n")
    elif raw == "empty":
        data = b""
    elif raw == "deep":
        kind = draw(st.sampled_from(["array", "inline", "dotted"]))
        depth = draw(st.sampled_from([10, 100, 500, 1_000, 10_000, 100_000]))
        data = data + _deep(kind, depth).encode()
        raw = f"deep {kind} {depth}"
    elif raw == "larger_than_read":
        size = MAX_READ + 1
    if raw != "none":
        done.append(("raw", raw))
    return CampaignCase(data, {CURVE: draw(curve_files())}, size, done)


# ---------------------------------------------------------------------------------------------
# argument lists, from the option tables of the built command

def cli_command():
    """The `rockcal` click command as `main` builds it (its registrations undone after)."""
    import typer

    from rockcal.cli import app as cli

    groups, commands = list(cli.app.registered_groups), list(cli.app.registered_commands)
    try:
        cli._register()
        return typer.main.get_command(cli.app)
    finally:
        cli.app.registered_groups[:] = groups
        cli.app.registered_commands[:] = commands


NUMBER_TEXT = ["0", "-0", "-1", "1", "nan", "NaN", "inf", "-inf", "+inf", "Infinity", "1e300", "-1e300",
               "1e-320", "5e-324", "1e309", str(2**63 - 1), str(-(2**63)), str(2**63), str(10**30),
               "9" * 5000, "1_000", "0x10", " 5 ", "", "abc", "1,5", "١٢", "½", "-", "5e", ".", "0.0000001"]
# argv comes from the OS: no NUL; a byte that is not UTF-8 arrives as a lone surrogate
ARG_TEXT = ["", " ", "a\nb", "\x1b[31m", "\u202e", "名前", "🪨", "\udcff", "a" * 5000, "--json",
            "--help", "-", "--", "=", "a=b=c"]
arg_text = st.one_of(_one_of_list(ARG_TEXT), _one_of_list(NUMBER_TEXT),
                     st.text(st.characters(exclude_characters="\x00"), max_size=20))
number_text = st.one_of(_one_of_list(NUMBER_TEXT), st.floats().map(repr), st.integers().map(str))
# paths an option may name: relative to the case's folder (its cwd), or ones nobody can write
PATH_TEXT = ["out", "campaign.toml", "campaign.toml/sub", "missing/deeper/out", "", ".", "a" * 300,
             "b/" * 2100, "/proc/rockcal-out", "/dev/null", "\udcff", "out/", "./out"]


INT_TEXT = ["0", "-1", "1", "2", str(2**31), str(2**63 - 1), str(2**63), str(-(2**63) - 1), str(10**30),
            "9" * 5000, "1.5", "1e3", "nan", "", "abc", "١٢", "0x10", "1_0", " 3"]


def _text(value) -> str:
    return repr(value) if isinstance(value, float) else str(value)


def option_values(param, info=None) -> st.SearchStrategy:
    """Text for an option by its annotation in the command's table, and by the constraints of
    the model field it sets (`info`), if any: the bound and its neighbours."""
    annotation = param.type_descriptor.annotation
    near = [_one_of_list([_text(b) for b in _bounds_of(info)])] if _bounds_of(info) else []
    if isinstance(annotation, type) and issubclass(annotation, enum.Enum):
        choices = [m.value for m in annotation]
        return st.one_of(_one_of_list(choices), _one_of_list([c.upper() for c in choices]), arg_text)
    if annotation is int:
        return st.one_of(*near, _one_of_list(INT_TEXT), st.integers().map(str), arg_text)
    if annotation is float:
        return st.one_of(*near, _one_of_list(NUMBER_TEXT), st.floats().map(repr), arg_text)
    if annotation is pathlib.Path:
        return st.one_of(_one_of_list(PATH_TEXT), arg_text)
    return st.one_of(arg_text, number_text)


def options_of(command) -> dict[str, Any]:
    """The options of a click command by their first flag."""
    return {p.opts[0]: p for p in command.params if p.param_type_name == "option"}


def set_values(model: str | None) -> st.SearchStrategy:
    """`--set NAME=VALUE`: a parameter of the material (its bounds and their neighbours from
    the material's parameter model, or an extreme number), another material's, or junk."""
    material = MATERIALS[model or DEFAULT_MATERIAL]
    fields = getattr(material.params_type, "model_fields", {})

    def value(name):
        near = [_one_of_list([_text(b) for b in _bounds_of(fields[name])])] if _bounds_of(fields.get(name)) else []
        return st.one_of(*near, number_text)

    own = [st.tuples(st.just(name), value(name)) for name in material.parameters]
    other = st.tuples(st.one_of(_one_of_list(NAMES), arg_text), number_text)
    return st.one_of(st.one_of(*own).map(lambda nv: f"{nv[0]}={nv[1]}"), other.map(lambda nv: f"{nv[0]}={nv[1]}"),
                     arg_text)


# ---------------------------------------------------------------------------------------------
# the flat-joint material's campaign keys: [search] bounds and fixed, [sensitivity] levels

FLAT_JOINT = "flatjoint"
ARRAYS = {"L4(2^3)": 2, "L9(3^4)": 3}  # small orthogonal arrays and their levels


def _parameter_values(model: str, name: str) -> st.SearchStrategy:
    """A value for one of `model`'s parameters: in its range mostly, else at or past a bound."""
    fields = MATERIALS[model].params_type.model_fields
    info = fields.get(name) or next((f for f in fields.values() if f.alias == name), None)
    if info is None:
        return numbers
    near = [_one_of_list(_bounds_of(info))] if _bounds_of(info) else []
    default = info.default if isinstance(info.default, (int, float)) and info.default else 1.0
    plain = st.floats(0.5, 2.0).map(lambda f: float(default * f))  # beside the default: mostly valid
    return st.one_of(plain, plain, plain, plain, _in_range_floats(info), *near, _one_of_list(FLOAT_EXTREMES[:8]))


def _parameter_lists(model: str, name: str, size: int) -> st.SearchStrategy:
    """`size` values of a parameter: increasing from beside its default mostly, else any."""
    fields = MATERIALS[model].params_type.model_fields if name in MATERIALS[model].parameters else {}
    info = fields.get(name) or next((f for f in fields.values() if f.alias == name), None)
    default = getattr(info, "default", None)
    default = default if isinstance(default, (int, float)) and default else 1.0
    rising = st.tuples(st.floats(0.5, 1.0), st.floats(1.2, 2.0)).map(
        lambda f: [float(default * (f[0] + k * (f[1] - f[0]) / (size - 1))) for k in range(size)])
    anything = st.lists(_parameter_values(model, name) if info is not None else numbers, min_size=size,
                        max_size=size)
    return st.one_of(rising, rising, rising, anything)


@st.composite
def flat_joint_cases(draw) -> CampaignCase:
    """The small campaign on the flat-jointed material, its search box, fixed values and
    sensitivity levels drawn over the material's parameters (now and then another material's),
    and samples around the fewest the box needs."""
    names = list(MATERIALS[FLAT_JOINT].parameters)
    others = [n for n in NAMES if n not in names]
    pick = st.one_of(*[st.sampled_from(names)] * 8, st.sampled_from(others), st.sampled_from(SEARCHED_GENESIS))
    doc = base_campaign()
    doc["material"] = {"model": FLAT_JOINT}
    bounds = {}
    for name in draw(st.lists(pick, min_size=0, max_size=3, unique=True)):
        model = FLAT_JOINT if name in names else DEFAULT_MATERIAL
        bounds[name] = draw(_parameter_lists(model, name, 2))
    fixed = {name: draw(_parameter_values(FLAT_JOINT if name in names else DEFAULT_MATERIAL, name))
             for name in draw(st.lists(st.one_of(*[st.sampled_from(names)] * 8, st.sampled_from(others)),
                                       max_size=2, unique=True))}
    doc["search"] = {"bounds": bounds, "fixed": fixed}
    if not bounds or draw(st.booleans()):
        array = draw(st.sampled_from(sorted(ARRAYS)))
        levels = {name: draw(_parameter_lists(FLAT_JOINT if name in names else DEFAULT_MATERIAL, name,
                                              ARRAYS[array]))
                  for name in draw(st.lists(pick.filter(lambda n: n not in SEARCHED_GENESIS),
                                            min_size=1, max_size=3, unique=True))}
        doc["sensitivity"] = {"array": array, "levels": levels}
    doc["surrogate"]["samples"] = draw(st.integers(4, 8))
    return CampaignCase(toml_dumps(doc).encode())

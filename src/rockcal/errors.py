"""The one exception type for a user's mistake; the CLI prints it in one line and exits 2."""

import difflib
import re
from typing import Callable, Mapping, get_args


class InputError(ValueError):
    """Bad input from a user: the message names the field and what is allowed."""

    def __init__(self, field: str, problem: str):
        self.field = field
        self.problem = problem
        super().__init__(f"{field}: {problem}")


class fields_named:
    """Within it, an InputError's field is renamed by `rename`: a function of the field, or a
    dict (a field it does not hold keeps its name); `reword`, a function of its message, may
    rewrite that too (the names the message gives)."""

    def __init__(self, rename: Callable[[str], str] | Mapping[str, str],
                 reword: Callable[[str], str] = lambda problem: problem):
        self.rename = (lambda field: rename.get(field, field)) if isinstance(rename, Mapping) else rename
        self.reword = reword

    def __enter__(self):
        return self

    def __exit__(self, kind, exc, tb):
        if isinstance(exc, InputError):
            field, problem = self.rename(exc.field), self.reword(exc.problem)
            if (field, problem) != (exc.field, exc.problem):
                raise InputError(field, problem) from None
        return False


def as_flags() -> fields_named:
    """Within it, an InputError naming a setting (notch_mm) names its CLI flag (--notch-mm)."""
    return fields_named(lambda field: field if field.startswith("-") else "--" + field.replace("_", "-"))


_UNION_TAGS = {"float", "int", "str", "bool"}  # pydantic's names of a union's members in a location


def from_validation_error(exc, model=None) -> InputError:
    """Turn a pydantic ValidationError into an InputError naming the first bad field; a
    validator's message "key: problem" names a key below the field it validated. With the
    `model` validated, an unknown key is told the known key it is closest to."""
    err = exc.errors()[0]
    path = [str(p) for p in err.get("loc", ()) if str(p) not in _UNION_TAGS and "[" not in str(p)]
    problem = err.get("msg", str(exc))
    if err.get("type") == "extra_forbidden" and model is not None and path:
        problem += _did_you_mean(path[-1], _fields_at(model, path[:-1]))
    cause = (err.get("ctx") or {}).get("error")
    if isinstance(cause, Exception):  # a validator's own message, without pydantic's prefix
        key, sep, rest = str(cause).partition(": ")
        if sep and re.fullmatch(r"[\w.]+", key):
            path, problem = path + [key], rest
        else:
            problem = str(cause)
    return InputError(".".join(map(key_text, path)) or "input", problem)


def key_text(name: str) -> str:
    """A key as an error names it: quoted where it is empty or holds a space or a quote."""
    return name if re.fullmatch(r"[^\s'\"]+", name) else repr(name)


def _fields_at(model, path: list[str]) -> list[str]:
    """The field names of the model found at `path` below `model` (none where it is not one)."""
    for name in path:
        field = getattr(model, "model_fields", {}).get(name)
        if field is None:
            return []
        model = next((t for t in (field.annotation, *get_args(field.annotation)) if hasattr(t, "model_fields")), None)
    return list(getattr(model, "model_fields", {}))


def _did_you_mean(name: str, known: list[str]) -> str:
    """"; did you mean KEY?" for the known key closest to `name`, if one is close."""
    close = difflib.get_close_matches(name, known, n=1, cutoff=0.6)
    return f"; did you mean {close[0]}?" if close else ""

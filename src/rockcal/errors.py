"""The one exception type for a user's mistake; the CLI prints it in one line and exits 2."""

import re
from typing import Callable, Mapping


class InputError(ValueError):
    """Bad input from a user: the message names the field and what is allowed."""

    def __init__(self, field: str, problem: str):
        self.field = field
        self.problem = problem
        super().__init__(f"{field}: {problem}")


class fields_named:
    """Within it, an InputError's field is renamed by `rename`: a function of the field, or a
    dict (a field it does not hold keeps its name)."""

    def __init__(self, rename: Callable[[str], str] | Mapping[str, str]):
        self.rename = (lambda field: rename.get(field, field)) if isinstance(rename, Mapping) else rename

    def __enter__(self):
        return self

    def __exit__(self, kind, exc, tb):
        if isinstance(exc, InputError) and self.rename(exc.field) != exc.field:
            raise InputError(self.rename(exc.field), exc.problem) from None
        return False


def as_flags() -> fields_named:
    """Within it, an InputError naming a setting (notch_mm) names its CLI flag (--notch-mm)."""
    return fields_named(lambda field: field if field.startswith("-") else "--" + field.replace("_", "-"))


_UNION_TAGS = {"float", "int", "str", "bool"}  # pydantic's names of a union's members in a location


def from_validation_error(exc) -> InputError:
    """Turn a pydantic ValidationError into an InputError naming the first bad field; a
    validator's message "key: problem" names a key below the field it validated."""
    err = exc.errors()[0]
    path = [str(p) for p in err.get("loc", ()) if str(p) not in _UNION_TAGS and "[" not in str(p)]
    problem = err.get("msg", str(exc))
    cause = (err.get("ctx") or {}).get("error")
    if isinstance(cause, Exception):  # a validator's own message, without pydantic's prefix
        key, sep, rest = str(cause).partition(": ")
        if sep and re.fullmatch(r"[\w.]+", key):
            path, problem = path + [key], rest
        else:
            problem = str(cause)
    return InputError(".".join(path) or "input", problem)

"""The one exception type for a user's mistake; the CLI prints it in one line and exits 2."""

import re


class InputError(ValueError):
    """Bad input from a user: the message names the field and what is allowed."""

    def __init__(self, field: str, problem: str):
        self.field = field
        self.problem = problem
        super().__init__(f"{field}: {problem}")


class as_flags:
    """Within it, an InputError naming a setting (notch_mm) names its CLI flag (--notch-mm)."""

    def __enter__(self):
        return self

    def __exit__(self, kind, exc, tb):
        if isinstance(exc, InputError) and not exc.field.startswith("-"):
            raise InputError("--" + exc.field.replace("_", "-"), exc.problem) from None
        return False


def from_validation_error(exc) -> InputError:
    """Turn a pydantic ValidationError into an InputError naming the first bad field; a
    validator's message "key: problem" names a key below the field it validated."""
    err = exc.errors()[0]
    path = [str(p) for p in err.get("loc", ())]
    problem = err.get("msg", str(exc))
    cause = (err.get("ctx") or {}).get("error")
    if isinstance(cause, Exception):  # a validator's own message, without pydantic's prefix
        key, sep, rest = str(cause).partition(": ")
        if sep and re.fullmatch(r"[\w.]+", key):
            path, problem = path + [key], rest
        else:
            problem = str(cause)
    return InputError(".".join(path) or "input", problem)

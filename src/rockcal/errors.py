"""The one exception type for a user's mistake; the CLI prints it in one line and exits 2."""


class InputError(ValueError):
    """Bad input from a user: the message names the field and what is allowed."""

    def __init__(self, field: str, problem: str):
        self.field = field
        self.problem = problem
        super().__init__(f"{field}: {problem}")


def from_validation_error(exc) -> InputError:
    """Turn a pydantic ValidationError into an InputError naming the first bad field."""
    err = exc.errors()[0]
    field = ".".join(str(p) for p in err.get("loc", ())) or "input"
    return InputError(field, err.get("msg", str(exc)))

"""The promise every command keeps for bad input, as the tests check it: the exit code (2 for
bad input), one line on stderr that starts as given and holds the words given, no traceback."""

ERROR = "rockcal: error: "


def assert_one_line(code: int, stderr: str, start: str = "", *words: str, exit_code: int = 2) -> str:
    """Assert the promise; the line."""
    assert code == exit_code, stderr
    assert "Traceback" not in stderr, stderr
    lines = stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(start), stderr
    for word in words:
        assert word in lines[0], lines[0]
    return lines[0]

"""User text (a rock name, a folder) made safe for the files rockcal generates: in a comment
of a PFC data file or script it stays on its line and is never read as code."""

from __future__ import annotations

import unicodedata

# characters that end a line, or reorder how a line is shown (bidirectional controls)
_BIDI = set("\u061c\u200e\u200f\u202a\u202b\u202c\u202d\u202e\u2066\u2067\u2068\u2069")


def comment_text(text: str) -> str:
    """`text` in printable ASCII: every other character as its Python escape (\\n, \\x1b,
    \\u2028), so that no line break, control or encoding trick leaves a comment line."""
    return "".join(c if " " <= c <= "~" else c.encode("unicode_escape").decode("ascii") for c in str(text))


def unsafe_character(text: str) -> str | None:
    """The first control, line-breaking or bidirectional character of `text`, escaped; None
    when it has none."""
    for c in text:
        if unicodedata.category(c) in ("Cc", "Cs", "Zl", "Zp") or c in _BIDI:
            return c.encode("unicode_escape").decode("ascii")
    return None

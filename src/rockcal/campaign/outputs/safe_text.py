"""User text (a rock name, a folder) checked for the files rockcal generates: a character that
could break or reorder a line is found (`unsafe_character`) and refused where the text is given;
a PFC file's comments escape whatever is left (`rockcal.pfc.header.comment_text`)."""

from __future__ import annotations

import unicodedata

# characters that end a line, or reorder how a line is shown (bidirectional controls)
_BIDI = set("\u061c\u200e\u200f\u202a\u202b\u202c\u202d\u202e\u2066\u2067\u2068\u2069")


def unsafe_character(text: str) -> str | None:
    """The first control, line-breaking or bidirectional character of `text`, escaped; None
    when it has none."""
    for c in text:
        if unicodedata.category(c) in ("Cc", "Cs", "Zl", "Zp") or c in _BIDI:
            return c.encode("unicode_escape").decode("ascii")
    return None

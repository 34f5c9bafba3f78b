"""Clear errors for bad names: what was wrong, the valid values, and the close matches."""

from __future__ import annotations

import difflib
from typing import Iterable


def close_matches_message(value: str, valid: Iterable[str], what: str) -> str:
    valid = list(valid)
    close = difflib.get_close_matches(str(value), valid, n=3, cutoff=0.5)
    hint = f" Did you mean {' or '.join(repr(c) for c in close)}?" if close else ""
    return f"Valid {what}s: {', '.join(valid)}.{hint}"


def check_choice(value: str, valid: Iterable[str], what: str) -> str:
    """Return ``value`` if it is one of ``valid``; raise ValueError naming the choices if not."""
    valid = list(valid)
    if value not in valid:
        raise ValueError(f"Unknown {what} {value!r}. " + close_matches_message(value, valid, what))
    return value

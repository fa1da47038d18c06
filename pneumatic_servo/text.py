"""Text forms shared by every layer: the command line's options and the nodes' parameters
read them alike."""
from __future__ import annotations


def comma_list(text: str) -> tuple[str, ...]:
    """A comma-separated list (``a,b,c``) as a tuple of its items, each stripped of spaces,
    empty items dropped (so ``''`` is ``()``)."""
    return tuple(item.strip() for item in text.split(',') if item.strip())

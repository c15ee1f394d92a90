"""The events a front hands a viewing session, checked where they arrive (no numpy, no GL).

A served page's WebSocket messages and a notebook's or a Python caller's ``Session.handle``
events are untrusted: ``checked(event)`` returns the event with each field the session reads
of the right type and within bounds, or raises InputError naming the field (``pointer_move
.x: expected a finite number ...``). The server drops such a message with one line; Python
gets the error. Fields the session does not read are left as they are; unknown kinds pass
(a page may send more than the viewer uses).
"""

from __future__ import annotations

import math

from ..errors import InputError

COORDINATE = 1e6  # |x|, |y|, |dx|, |dy| in CSS pixels: beyond any screen
SIDE = 1 << 16  # width, height in CSS pixels
RATIO = (0.0, 16.0)  # pixel_ratio (0: a hidden view, kept at its last size)
# field: (lowest, highest) of the numbers the session reads
NUMBERS = {"x": (-COORDINATE, COORDINATE), "y": (-COORDINATE, COORDINATE),
           "dx": (-COORDINATE, COORDINATE), "dy": (-COORDINATE, COORDINATE),
           "width": (0.0, SIDE), "height": (0.0, SIDE), "pixel_ratio": RATIO, "ratio": RATIO}
WHOLE = {"button": (0, 16), "index": (0, 1 << 53)}  # whole numbers
TEXT = 64  # the longest key name
MODIFIERS = 8  # the most modifiers one event holds


def checked(event) -> dict:
    """``event`` (a dict of the session's vocabulary, facet.viewing.session) when every field
    the session reads is valid; InputError naming the first that is not."""
    if not isinstance(event, dict):
        raise InputError(f"an event must be an object with a \"type\", got "
                         f"{type(event).__name__}")
    kind = event.get("type", event.get("event_type"))
    if not isinstance(kind, str) or len(kind) > TEXT:
        raise InputError(f"an event's \"type\" must be a short text, got {_shown(kind)}")
    out = dict(event)
    for name, (low, high) in NUMBERS.items():
        if name in event and not (name == "pixel_ratio" and event[name] is None):
            value = event[name]
            if isinstance(value, bool) or not isinstance(value, (int, float)) or \
                    not math.isfinite(value) or not low <= value <= high:
                raise InputError(f"{kind}.{name}: expected a finite number from {low:g} to "
                                 f"{high:g}, got {_shown(value)}")
            out[name] = float(value)
    for name, (low, high) in WHOLE.items():
        if name in event:
            value = event[name]
            if isinstance(value, bool) or not isinstance(value, (int, float)) or \
                    not math.isfinite(value) or value != int(value) or \
                    not low <= value <= high:
                raise InputError(f"{kind}.{name}: expected a whole number from {low} to "
                                 f"{high}, got {_shown(value)}")
            out[name] = int(value)
    if "key" in event and (not isinstance(event["key"], str) or len(event["key"]) > TEXT):
        raise InputError(f"{kind}.key: expected a key's name (text), got "
                         f"{_shown(event['key'])}")
    if "modifiers" in event:
        mods = event["modifiers"]
        if not isinstance(mods, (list, tuple)) or len(mods) > MODIFIERS or \
                not all(isinstance(m, str) and len(m) <= TEXT for m in mods):
            raise InputError(f"{kind}.modifiers: expected a list of names such as "
                             f"[\"Shift\"], got {_shown(mods)}")
    return out


def _shown(value) -> str:
    """A value for a message: its repr, cut short."""
    text = repr(value)
    return text if len(text) <= 40 else text[:37] + "..."

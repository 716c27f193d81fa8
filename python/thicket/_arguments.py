"""Argument checks that the pure-Python parts of the module share."""

import operator


def count(value, name, what, least=0):
    """value as an int of at least `least`: TypeError for a bool or a non-integer, ValueError
    saying it must be `what` below `least`, both naming `name`."""
    if isinstance(value, bool):
        raise TypeError(f"{name} must be an int, not bool")
    try:
        n = operator.index(value)
    except TypeError:
        raise TypeError(f"{name} must be an int, got {type(value).__name__} {value!r}") from None
    if n < least:
        raise ValueError(f"{name} must be {what}, got {n}")
    return n

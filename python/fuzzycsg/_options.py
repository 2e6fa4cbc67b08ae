"""Keyword arguments onto the library's option structs.

Each engine's options are a class of the compiled module whose attributes are the fields of the
library's struct (``FitOptions.prims``, ``ConvertOptions.time_limit``, ...). A keyword argument
sets the field of its name; a nested struct (``sampling``, ``metrics``, ``local``) takes a dict.
An unknown name is a TypeError, as for any Python function; a value out of range is the
library's OptionError, naming the field.
"""

from __future__ import annotations


def options_from(cls, kwargs: dict, fn: str):
    """An instance of ``cls`` with the fields named in ``kwargs`` set."""
    options = cls()
    _apply(options, kwargs, fn, "")
    return options


def _apply(options, kwargs: dict, fn: str, prefix: str) -> None:
    for name, value in kwargs.items():
        field = prefix + name
        if name.startswith("_") or not hasattr(options, name):
            known = ", ".join(sorted(n for n in dir(options) if not n.startswith("_")))
            raise TypeError(f"{fn}() got an unexpected option '{field}' (options: {known})")
        current = getattr(options, name)
        if isinstance(value, dict) and not isinstance(current, (int, float, str, bool, list)):
            _apply(current, value, fn, field + ".")
            setattr(options, name, current)
            continue
        try:
            setattr(options, name, value)
        except TypeError:
            raise TypeError(
                f"{fn}(): {field}: expected {type(current).__name__}, got {type(value).__name__}"
            ) from None


def fields(options) -> dict:
    """The fields of an options instance as a dict (nested structs as dicts)."""
    out = {}
    for name in dir(options):
        if name.startswith("_"):
            continue
        value = getattr(options, name)
        if callable(value):
            continue
        if not isinstance(value, (int, float, str, bool, list, tuple)):
            value = fields(value)
        out[name] = value
    return out

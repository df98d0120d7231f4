# SPDX-License-Identifier: BSD-3-Clause
"""Checks of the Python API's arguments before they reach the compiled core: a wrong type or
value is a ``vrsph.Error`` subclass naming the parameter (never pybind11's "Unable to cast
Python instance to C++ type", never a silently truncated or defaulted value)."""
from __future__ import annotations

import math
import numbers
from typing import Any, Sequence

from ._vrsph import ConfigError, Error


class ArgumentTypeError(Error, TypeError):
    """An argument of the wrong type (also a ``TypeError``)."""


def _kind(value: Any) -> str:
    return type(value).__name__


def number(value: Any, name: str, *, positive: bool = False, minimum: float | None = None) -> float:
    """A finite real number (not a bool, not a string)."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise ArgumentTypeError(f"the parameter {name} must be a number, got {_kind(value)} {value!r}")
    v = float(value)
    if not math.isfinite(v):
        raise ConfigError(f"the parameter {name} must be finite, got {v}")
    if positive and not v > 0:
        raise ConfigError(f"the parameter {name} must be > 0, got {v}")
    if minimum is not None and v < minimum:
        raise ConfigError(f"the parameter {name} must be >= {minimum}, got {v}")
    return v


def optional_length(value: Any, name: str) -> float:
    """A support radius: None (0.0 for the core: from the h-factor) or a finite number > 0."""
    return 0.0 if value is None else number(value, name, positive=True)


def integer(value: Any, name: str, *, minimum: int | None = None, maximum: int | None = None) -> int:
    """An integer; a float is accepted only when it is one exactly (8.0, not 8.7)."""
    if isinstance(value, bool):
        raise ArgumentTypeError(f"the parameter {name} must be an integer, got bool {value!r}")
    if isinstance(value, numbers.Integral):
        v = int(value)
    elif isinstance(value, numbers.Real) and math.isfinite(float(value)) and float(value).is_integer():
        v = int(value)
    elif isinstance(value, numbers.Real):
        raise ConfigError(f"the parameter {name} must be an integer, got {value!r}")
    else:
        raise ArgumentTypeError(f"the parameter {name} must be an integer, got {_kind(value)} {value!r}")
    if minimum is not None and v < minimum:
        raise ConfigError(f"the parameter {name} must be >= {minimum}, got {v}")
    if maximum is not None and v > maximum:
        raise ConfigError(f"the parameter {name} must be <= {maximum}, got {v}")
    return v


def integers(values: Any, name: str, *, minimum: int | None = None) -> list[int]:
    """A non-empty sequence of integers (a single integer is a list of one)."""
    if isinstance(values, (str, bytes)) or not isinstance(values, (Sequence, numbers.Integral)) and not hasattr(
            values, "__iter__"):
        raise ArgumentTypeError(f"the parameter {name} must be a list of integers, got {_kind(values)} {values!r}")
    items = [values] if isinstance(values, numbers.Number) else list(values)
    if not items:
        raise ConfigError(f"the parameter {name} needs at least one value")
    return [integer(v, f"{name}[{k}]", minimum=minimum) for k, v in enumerate(items)]


def text(value: Any, name: str) -> str:
    """A string option (a method, kernel or solver name)."""
    if not isinstance(value, str):
        raise ArgumentTypeError(f"the parameter {name} must be a string, got {_kind(value)} {value!r}")
    return value


def optional_text(value: Any, name: str) -> str | None:
    return None if value is None else text(value, name)


def pressure_corrections(value: Any) -> int | None:
    """FlowOptions::pressure_corrections: None lets the flow pick (1 with VRSPH, else 0), else 0-10."""
    return None if value is None else integer(value, "pressure_corrections", minimum=0, maximum=10)


def expression(value: Any, name: str) -> str | None:
    """An expression in x, y, z: a string, or a number (a constant, as documented)."""
    if value is None or isinstance(value, str):
        return value
    if isinstance(value, numbers.Real) and not isinstance(value, bool):
        return repr(number(value, name))
    raise ArgumentTypeError(f"the parameter {name} must be an expression string or a number, got "
                            f"{_kind(value)} {value!r}")


def expressions(values: Any, name: str) -> list[str] | None:
    """One expression, or a sequence of them (one per direction or boundary piece)."""
    if values is None:
        return None
    if isinstance(values, (str, numbers.Real)) and not isinstance(values, bool):
        return [expression(values, name)]
    if not hasattr(values, "__iter__"):
        raise ArgumentTypeError(f"the parameter {name} must be a list of expressions, got {_kind(values)} {values!r}")
    return [expression(v, f"{name}[{k}]") for k, v in enumerate(values)]


def names(values: Any, name: str) -> list[str]:
    """One name or a sequence of names (methods)."""
    if isinstance(values, str):
        return [values]
    if not hasattr(values, "__iter__"):
        raise ArgumentTypeError(f"the parameter {name} must be a name or a list of names, got {_kind(values)} {values!r}")
    out = [text(v, f"{name}[{k}]") for k, v in enumerate(values)]
    if not out:
        raise ConfigError(f"the parameter {name} needs at least one name")
    return out


def flag(value: Any, name: str) -> bool:
    if not isinstance(value, (bool, numbers.Integral)) or isinstance(value, numbers.Integral) and value not in (0, 1):
        raise ArgumentTypeError(f"the parameter {name} must be True or False, got {_kind(value)} {value!r}")
    return bool(value)


def options(value: Any, name: str) -> dict:
    """Method options {key: value}."""
    if value is None:
        return {}
    if not hasattr(value, "items"):
        raise ArgumentTypeError(f"the parameter {name} must be a mapping of option names to values, got "
                                f"{_kind(value)} {value!r}")
    return {text(k, f"{name} key"): v for k, v in value.items()}


def per_method_options(value: Any, name: str) -> dict:
    """{method: {key: value}}."""
    return {m: options(o, f"{name}[{m!r}]") for m, o in options(value, name).items()}


def neighbour_list(value: Any, name: str, particles: int):
    """``(indptr, indices)`` or ``(indptr, indices, distances)``, or a SciPy sparse matrix whose
    pattern is the list: int32 row pointers and indices, float64 distances or None."""
    import numpy as np

    if value is None:
        return None
    if hasattr(value, "tocsr") and hasattr(value, "shape"):  # a SciPy sparse matrix: its pattern
        m = value.tocsr()
        if m.shape != (particles, particles):
            raise ConfigError(f"{name}: a sparse matrix of shape {m.shape} for {particles} particles")
        value = (m.indptr, m.indices)
    if not isinstance(value, (tuple, list)) or len(value) not in (2, 3):
        raise ArgumentTypeError(f"{name} must be (indptr, indices), (indptr, indices, distances) or a SciPy sparse "
                                f"matrix, got {_kind(value)}")
    out = []
    for part, label in zip(value[:2], ("indptr", "indices")):
        a = np.asarray(part)
        if a.ndim != 1 or not np.issubdtype(a.dtype, np.integer):
            raise ArgumentTypeError(f"{name}: {label} must be a 1D array of integers, got {a.dtype} of shape {a.shape}")
        if a.size and (a.min() < -2**31 or a.max() >= 2**31):
            raise ConfigError(f"{name}: {label} holds values beyond a 32-bit index")
        out.append(np.ascontiguousarray(a, dtype=np.int32))
    distances = None
    if len(value) == 3 and value[2] is not None:
        d = np.asarray(value[2])
        if d.ndim != 1 or not np.issubdtype(d.dtype, np.number):
            raise ArgumentTypeError(f"{name}: distances must be a 1D array of numbers, got {d.dtype} of shape {d.shape}")
        distances = np.ascontiguousarray(d, dtype=np.float64)
    return out[0], out[1], distances

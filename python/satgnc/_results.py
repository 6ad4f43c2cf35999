"""The one result style of satgnc (private).

Every result a public function returns is a frozen dataclass derived from :class:`Result`:

* fields are attributes (``r.status``, ``r.iterations``, ``r.X``); assigning one raises
  :class:`dataclasses.FrozenInstanceError`;
* numpy arrays are copied at construction and stored read-only (``flags.writeable = False``), also
  inside list and tuple fields: writing into one raises ``ValueError``. ``r.X.copy()`` gives a
  writeable array;
* results that used to be dicts still answer ``r["X"]`` (and ``"X" in r``, ``r.keys()``,
  ``r.get("X")``), with a ``DeprecationWarning`` that names the attribute to use instead; the value is
  the attribute itself (``r["X"] is r.X``);
* ``repr(r)`` is one line: scalars and strings as values, arrays as ``<float64 array 61x6>``,
  sequences and mappings as their length, nested results as their class (never an array's entries or
  an address; checked for every subclass by tests/python/test_reprs.py);
* solver results carry ``status: str`` (a snake_case name such as ``"solved"``), ``message: str``
  and ``iterations: int``.

:func:`deprecated`, :func:`deprecated_function` and :func:`module_getattr` give renamed or moved
public names their deprecated aliases: the old name keeps its old behaviour and warns with the new
name.
"""

from __future__ import annotations

import dataclasses
import functools
import threading
import warnings
from collections.abc import Callable, Iterator, Mapping
from typing import Any, TypeVar

import numpy as np

__all__ = ["Result", "adopt", "adopt_dict", "deprecated", "deprecated_function", "module_getattr", "readonly"]

_F = TypeVar("_F", bound=Callable[..., Any])
_R = TypeVar("_R", bound="Result")


_CONTAINERS = (np.ndarray, list, tuple)


def _holds_arrays(seq: list[Any] | tuple[Any, ...]) -> bool:
    """Whether a list / tuple field holds arrays or nested sequences. Result fields are homogeneous
    (stairs and indices are lists of ints, modes a list of arrays): the first and last items tell,
    without a scan of every entry (a Python loop over a 50-entry list cost ~5 us per field)."""
    return bool(seq) and (isinstance(seq[0], _CONTAINERS) or isinstance(seq[-1], _CONTAINERS))


def readonly(value: Any) -> Any:
    """A read-only copy of ``value`` when it is a numpy array (lists and tuples: element-wise, the
    container type kept); any other value is returned as is."""
    if isinstance(value, np.ndarray):
        arr = value.copy()  # C order
        arr.flags.writeable = False
        return arr
    if isinstance(value, (list, tuple)) and _holds_arrays(value):
        items = [readonly(v) for v in value]
        return items if isinstance(value, list) else type(value)(items)
    return value


_ADOPT = threading.local()


def _freeze_in_place(value: Any) -> Any:
    """``value`` with its numpy arrays marked read-only without a copy (lists / tuples element-wise)."""
    if isinstance(value, np.ndarray):
        value.flags.writeable = False
        return value
    if isinstance(value, (list, tuple)) and _holds_arrays(value):
        items = [_freeze_in_place(v) for v in value]
        return items if isinstance(value, list) else type(value)(items)
    return value


def adopt(cls: type[_R], /, **fields: Any) -> _R:
    """``cls(**fields)`` taking ownership of the arrays in ``fields`` instead of copying them.

    For arrays the extension has just returned (and views of them) that nothing else references:
    they are marked read-only in place. Saves the copy (~10 us for a 50 x 50 staircase report, a
    tenth of a small ADMM solve). Never pass an array a caller may still hold.

    The hot path of every solve(): for a result class whose ``__init__`` is the one dataclasses
    generates and whose ``__post_init__`` is :class:`Result`'s, the object is filled directly (the
    defaults, then ``fields``), which is what that ``__init__`` and ``__post_init__`` do, without
    their per-field calls (L1Solver.solve(): 12 -> 5 us for 35 fields). Anything else, and any call
    with an unknown or a missing field, goes through ``cls(**fields)`` (its errors unchanged)."""
    layout = _LAYOUT.get(cls, False)
    if layout is False:
        layout = _LAYOUT[cls] = _direct_layout(cls)
    if layout is not None:
        names, required, defaults = layout
        if required <= fields.keys() <= names:
            obj = object.__new__(cls)
            d = obj.__dict__
            d.update(defaults)
            for name, value in fields.items():
                d[name] = _freeze_in_place(value) if isinstance(value, _CONTAINERS) else value
            return obj
    _ADOPT.on = True
    try:
        return cls(**fields)
    finally:
        _ADOPT.on = False


def adopt_dict(cls: type[_R], fields: dict[str, Any], arrays: tuple[str, ...]) -> _R:
    """:func:`adopt` for a dict the extension has just returned, already holding ``cls``'s field names:
    takes ownership of ``fields`` itself (no ``**`` repacking) and freezes only the ``arrays`` keys
    (the fields that can hold an array; the caller names them all). The per-call path of
    L1Solver.solve(): 9.3 -> 4.5 us for 35 fields (thread time, a 1-iteration N = 10 solve).
    Anything :func:`adopt` would not fill directly goes through it unchanged."""
    layout = _LAYOUT.get(cls, False)
    if layout is False:
        layout = _LAYOUT[cls] = _direct_layout(cls)
    if layout is None or not (layout[1] <= fields.keys() <= layout[0]):
        return adopt(cls, **fields)
    obj = object.__new__(cls)
    d = obj.__dict__
    d.update(layout[2])
    d.update(fields)
    for name in arrays:
        value = d[name]
        if type(value) is np.ndarray:
            value.setflags(write=False)
        elif isinstance(value, _CONTAINERS):
            d[name] = _freeze_in_place(value)
    return obj


def _direct_layout(cls: type) -> tuple[frozenset[str], frozenset[str], dict[str, Any]] | None:
    """(field names, required names, defaults) when adopt() may fill ``cls`` directly, else None:
    a dataclass with the generated ``__init__`` (every field an init field, plain scalar defaults, no
    default_factory) and Result's ``__post_init__``."""
    init = cls.__dict__.get("__init__")
    code = getattr(init, "__code__", None)
    if code is None or code.co_filename != "<string>" or cls.__post_init__ is not Result.__post_init__:
        return None
    fs = dataclasses.fields(cls)
    if any(not f.init or f.default_factory is not dataclasses.MISSING
           or isinstance(f.default, _CONTAINERS) for f in fs):
        return None
    names = frozenset(f.name for f in fs)
    required = frozenset(f.name for f in fs if f.default is dataclasses.MISSING)
    return names, required, {f.name: f.default for f in fs if f.default is not dataclasses.MISSING}


_LAYOUT: dict[type, tuple[frozenset[str], frozenset[str], dict[str, Any]] | None] = {}


def deprecated(old: str, new: str, *, stacklevel: int = 2) -> None:
    """Emit ``DeprecationWarning("<old> is deprecated; use <new>")`` at the caller's caller
    (``stacklevel`` as in :func:`warnings.warn`, counted from the function calling this one)."""
    warnings.warn(f"{old} is deprecated; use {new}", DeprecationWarning, stacklevel=stacklevel + 1)


def deprecated_function(func: _F, old: str, new: str) -> _F:
    """``func`` wrapped so that every call first warns "<old> is deprecated; use <new>"."""

    @functools.wraps(func)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        deprecated(old, new, stacklevel=2)
        return func(*args, **kwargs)

    return wrapper  # type: ignore[return-value]


def module_getattr(
    module: str, aliases: Mapping[str, tuple[str, Callable[[], Any]]]
) -> Callable[[str], Any]:
    """A module ``__getattr__`` serving deprecated names.

    ``aliases`` maps an old name to ``(new, load)``: reading ``module.old`` warns
    "<module>.<old> is deprecated; use <new>" and returns ``load()`` (the old object, unchanged).
    Any other missing name is an ``AttributeError`` as usual. Use as
    ``__getattr__ = module_getattr(__name__, {...})``."""
    table = dict(aliases)

    def __getattr__(name: str) -> Any:
        entry = table.get(name)
        if entry is None:
            raise AttributeError(f"module {module!r} has no attribute {name!r}")
        new, load = entry
        deprecated(f"{module}.{name}", new, stacklevel=2)
        return load()

    return __getattr__


_FIELD_NAMES: dict[type, tuple[str, ...]] = {}


def _summary(value: Any, depth: int = 0) -> str:
    """The short text of one field in a result's repr (see :meth:`Result.__repr__`)."""
    if value is None or isinstance(value, (bool, int, np.integer, np.bool_)):
        return repr(value.item() if isinstance(value, (np.integer, np.bool_)) else value)
    if isinstance(value, (float, np.floating)):
        return f"{float(value):.6g}"
    if isinstance(value, str):
        return repr(value if len(value) <= 60 else value[:57] + "...")
    if isinstance(value, np.ndarray):
        if value.size == 1 and value.ndim <= 1:
            return f"array([{_summary(value.reshape(-1)[0])}])"
        return f"<{value.dtype} array {'x'.join(map(str, value.shape)) or 'scalar'}>"
    if isinstance(value, Result) or dataclasses.is_dataclass(value):
        return f"<{type(value).__name__}>"
    if isinstance(value, Mapping):
        return f"<dict of {len(value)}>"
    if isinstance(value, (list, tuple)):
        if len(value) <= 4 and depth == 0 and all(
                isinstance(v, (bool, int, float, str, np.number)) and not isinstance(v, np.ndarray)
                for v in value):
            inner = ", ".join(_summary(v, depth + 1) for v in value)
            return f"[{inner}]" if isinstance(value, list) else f"({inner})"
        return f"<{type(value).__name__} of {len(value)}>"
    if hasattr(value, "name") and hasattr(value, "value") and type(value).__module__ != "builtins":
        return str(value.name)  # an enum (Python or pybind11)
    text = repr(value)
    plain = len(text) <= 60 and "\n" not in text and " at 0x" not in text
    return text if plain else f"<{type(value).__name__}>"


@dataclasses.dataclass(frozen=True)
class Result:
    """Base of every satgnc result: a frozen dataclass with read-only numpy arrays.

    Subclasses are declared with ``@dataclasses.dataclass(frozen=True)``; a subclass that defines
    ``__post_init__`` calls ``super().__post_init__()`` first. Dict-style access (``r["X"]``) is
    deprecated: it warns and returns ``r.X``."""

    def __init_subclass__(cls, **kw: Any) -> None:
        # The dataclass decorator writes a field-by-field repr (every array in full) unless the class
        # body defines one: give each subclass the summary repr first, so the decorator keeps it.
        super().__init_subclass__(**kw)
        if "__repr__" not in cls.__dict__:
            cls.__repr__ = Result.__repr__  # type: ignore[method-assign]

    def __repr__(self) -> str:
        """A one-line summary: scalars and strings as values, arrays as dtype and shape, sequences,
        mappings and nested results as their size or class (never an array's entries)."""
        names = _FIELD_NAMES.get(type(self)) or tuple(f.name for f in dataclasses.fields(self))
        parts = [f"{n}={_summary(getattr(self, n, None))}" for n in names]
        return f"{type(self).__name__}({', '.join(parts)})"

    def __post_init__(self) -> None:
        # the hot path of every solve() that returns a Result: field names cached per class, and the
        # instance dict written directly (what object.__setattr__ does for a frozen dataclass)
        names = _FIELD_NAMES.get(type(self))
        if names is None:
            names = _FIELD_NAMES[type(self)] = tuple(f.name for f in dataclasses.fields(self))
        # adopt() applies to this object's own fields only: the flag is consumed here, before any
        # result built inside a subclass's __post_init__
        own = getattr(_ADOPT, "on", False)
        _ADOPT.on = False
        freeze = _freeze_in_place if own else readonly
        d = self.__dict__
        for name in names:
            value = d[name]
            if isinstance(value, (np.ndarray, list, tuple)):
                d[name] = freeze(value)

    def __setstate__(self, state: dict[str, Any]) -> None:
        """Unpickling and copy.copy / deepcopy keep the arrays read-only."""
        for key, value in state.items():
            object.__setattr__(self, key, readonly(value))

    # ------------------------------------------------------------------ deprecated dict access
    def _field_names(self) -> list[str]:
        return [f.name for f in dataclasses.fields(self)]

    def __getitem__(self, key: str) -> Any:
        cls = type(self).__name__
        if not isinstance(key, str) or key not in self._field_names():
            raise KeyError(key)
        deprecated(f"{cls}[{key!r}] (dict access)", f"the attribute {cls}.{key}", stacklevel=2)
        return getattr(self, key)

    def __contains__(self, key: object) -> bool:
        deprecated(f"'key' in {type(self).__name__} (dict access)", "hasattr() or the attribute",
                   stacklevel=2)
        return isinstance(key, str) and key in self._field_names()

    def get(self, key: str, default: Any = None) -> Any:
        """Deprecated dict-style ``get``: use the attribute."""
        cls = type(self).__name__
        deprecated(f"{cls}.get({key!r}) (dict access)", f"the attribute {cls}.{key}", stacklevel=2)
        return getattr(self, key) if key in self._field_names() else default

    def keys(self) -> list[str]:
        """Deprecated dict-style ``keys``: the field names (see :func:`dataclasses.fields`)."""
        deprecated(f"{type(self).__name__}.keys() (dict access)", "dataclasses.fields()", stacklevel=2)
        return self._field_names()

    def __iter__(self) -> Iterator[str]:
        deprecated(f"iterating a {type(self).__name__} (dict access)", "dataclasses.fields()", stacklevel=2)
        return iter(self._field_names())

"""Argument checks shared by every satgnc room (private).

Every public function validates its arguments here before calling the engine. The rules:

* arrays are real: complex, boolean, object and string arrays are a ``TypeError`` naming the
  argument (numpy would truncate complex silently and read booleans as 0/1);
* numbers are real and finite unless a function allows infinity; ``bool`` is not a number;
* shapes are checked with the expected shape in the message;
* every message starts with the argument's name, then the rule, then what was given.

Files (CSV, TDM, TOML) are read through :func:`read_text_file`, and every error in a file's content
is a :class:`FileFormatError` naming the file and, where one exists, the line and the keyword or
column. TOML tables are checked against a strict typed schema by :func:`check_toml_table`.
"""

from __future__ import annotations

import dataclasses
import difflib
import functools
import math
import numbers
import os
import pathlib
import re
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

__all__ = [
    "FileFormatError",
    "Key",
    "as_bool",
    "as_finite_positive",
    "as_float_array",
    "as_int",
    "as_matrix",
    "as_real",
    "as_real_array",
    "as_scale",
    "as_series",
    "as_vector",
    "check_magnitude",
    "check_toml_table",
    "did_you_mean",
    "harden_module",
    "load_toml",
    "one_of",
    "read_text_file",
    "toml_line",
]

_REAL_KINDS = "fiu"  # float, signed and unsigned integer


def _describe(value: Any) -> str:
    if isinstance(value, np.ndarray):
        return f"array of dtype {value.dtype}"
    return type(value).__name__


def as_real_array(
    value: Any,
    name: str,
    *,
    ndim: int | tuple[int, ...] | None = None,
    shape: tuple[int | None, ...] | None = None,
    finite: bool = True,
    allow_inf: bool = False,
    copy: bool = False,
) -> np.ndarray:
    """Return ``value`` as a float64 array, or raise naming ``name``.

    ``shape`` may hold ``None`` for a free dimension. ``allow_inf`` admits +-inf (bounds) but never
    NaN. Complex, boolean, object and string input is a ``TypeError``."""
    if value is None or isinstance(value, (str, bytes, bool, np.bool_)):
        raise TypeError(f"{name}: must be a real numeric array, got {_describe(value)}")
    if isinstance(value, np.ndarray):
        arr = value
    else:
        try:
            arr = np.asarray(value)
        except (TypeError, ValueError) as e:  # ragged nested sequences
            raise TypeError(f"{name}: must be a real numeric array ({e})") from None
    if arr.dtype.kind not in _REAL_KINDS:
        kind = {"c": "complex", "b": "boolean", "O": "object", "U": "string", "S": "bytes"}.get(
            arr.dtype.kind, str(arr.dtype)
        )
        raise TypeError(f"{name}: must be a real numeric array, got a {kind} array")
    arr = np.array(arr, dtype=np.float64, copy=True) if copy else np.asarray(arr, dtype=np.float64)
    if ndim is not None:
        dims = (ndim,) if isinstance(ndim, int) else tuple(ndim)
        if arr.ndim not in dims:
            want = " or ".join(str(d) for d in dims)
            raise ValueError(f"{name}: must have {want} dimension(s), got shape {arr.shape}")
    if shape is not None:
        ok = arr.ndim == len(shape) and all(s is None or s == a for s, a in zip(shape, arr.shape))
        if not ok:
            dims = ", ".join("n" if s is None else str(s) for s in shape)
            want = f"({dims},)" if len(shape) == 1 else f"({dims})"
            raise ValueError(f"{name}: must have shape {want}, got {arr.shape}")
    if finite:
        bad = np.isnan(arr) if allow_inf else ~np.isfinite(arr)
        if np.any(bad):
            rule = "must not contain NaN" if allow_inf else "must be finite (no NaN or Inf)"
            raise ValueError(f"{name}: {rule}")
    return arr


def as_real(
    value: Any,
    name: str,
    *,
    positive: bool = False,
    nonnegative: bool = False,
    finite: bool = True,
    low: float | None = None,
    high: float | None = None,
) -> float:
    """Return ``value`` as a float, or raise naming ``name``. ``bool`` and complex are TypeErrors."""
    if type(value) is float:  # fast path: the numbers.Real ABC check costs ~1 us per argument
        pass
    elif isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        if isinstance(value, np.ndarray) and value.ndim == 0 and value.dtype.kind in _REAL_KINDS:
            value = value.item()
        else:
            raise TypeError(f"{name}: must be a real number, got {_describe(value)}")
    v = float(value)
    if math.isnan(v) or (finite and not math.isfinite(v)):
        raise ValueError(f"{name}: must be finite, got {v}")
    if positive and not v > 0:
        raise ValueError(f"{name}: must be > 0, got {v}")
    if nonnegative and not v >= 0:
        raise ValueError(f"{name}: must be >= 0, got {v}")
    if low is not None and v < low:
        raise ValueError(f"{name}: must be >= {low}, got {v}")
    if high is not None and v > high:
        raise ValueError(f"{name}: must be <= {high}, got {v}")
    return v


def as_int(value: Any, name: str, *, low: int | None = None, high: int | None = None) -> int:
    """Return ``value`` as an int, or raise naming ``name``. Floats (even 2.0) and bools are
    TypeErrors: a count is never rounded silently."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Integral):
        raise TypeError(f"{name}: must be an integer, got {_describe(value)}")
    v = int(value)
    if low is not None and v < low:
        raise ValueError(f"{name}: must be >= {low}, got {v}")
    if high is not None and v > high:
        raise ValueError(f"{name}: must be <= {high}, got {v}")
    return v


def as_bool(value: Any, name: str) -> bool:
    """Return ``value`` if it is a bool (Python or numpy); strings like "false" are TypeErrors."""
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    raise TypeError(f"{name}: must be true or false (a bool), got {_describe(value)}")


def one_of(value: Any, name: str, choices: Sequence[str]) -> str:
    """Return ``value`` if it is one of the strings ``choices``, or raise naming ``name``."""
    if not isinstance(value, str):
        raise TypeError(f"{name}: must be one of {list(choices)}, got {_describe(value)}")
    if value not in choices:
        raise ValueError(f"{name}: must be one of {list(choices)}, got {value!r}")
    return value



# ----------------------------------------------------------------------------- room-specific wordings
# The rooms' former private checkers, kept here with their exact messages (tests match them).


def check_magnitude(arr: np.ndarray, name: str, limit: float, why: str, *, subject: str = "entries",
                    detail: str | None = None, limit_text: str | None = None) -> np.ndarray:
    """``arr``, or ``ValueError("<name>: <subject> must be below <limit> in magnitude (<detail>): <why>")``
    when ``max |arr| >= limit`` (``detail`` defaults to ``got {big}``, where ``{big}`` is the largest
    magnitude; ``limit`` prints as ``1e100`` unless ``limit_text`` is given)."""
    big = float(np.max(np.abs(arr))) if np.size(arr) else 0.0
    if big >= limit:
        lim = limit_text if limit_text is not None else f"{limit:.0e}".replace("e+", "e")
        det = (detail if detail is not None else "got {big}").replace("{big}", f"{big:.3g}")
        raise ValueError(f"{name}: {subject} must be below {lim} in magnitude ({det}): {why}")
    return arr


def as_matrix(value: Any, name: str, ndim: int = 2, *, allow_empty: bool = False,
              vector_as: str | None = None) -> np.ndarray:
    """A finite real ``ndim``-D array (``"<name>: must be 2-D, got shape ..."``); ``vector_as``
    ``"column"`` / ``"row"`` reads a 1-D input as an (n, 1) / (1, n) matrix. Empty is refused unless
    ``allow_empty``."""
    a = as_real_array(value, name, finite=False)
    if ndim == 2 and a.ndim == 1 and vector_as == "column":
        a = a.reshape(-1, 1)
    if ndim == 2 and a.ndim == 1 and vector_as == "row":
        a = a.reshape(1, -1)
    if a.ndim != ndim:
        raise ValueError(f"{name}: must be {ndim}-D, got shape {a.shape}")
    if a.size == 0 and not allow_empty:
        raise ValueError(f"{name}: must not be empty (shape {a.shape})")
    if not np.all(np.isfinite(a)):
        raise ValueError(f"{name}: must be finite (no NaN or Inf)")
    return a


def as_scale(value: Any, name: str, unit: str, *, limit: float = 1e100) -> float:
    """A positive rate or length in ``[1/limit, limit]`` (its powers up to the third stay normal
    doubles); ``unit`` is named in the message."""
    v = as_real(value, name, positive=True)
    if not 1.0 / limit <= v <= limit:
        raise ValueError(f"{name}: must be in [1e-100, 1e100] {unit}, got {v:.3g} (its square or cube in the "
                         "model would overflow or underflow; hint: check the units)")
    return v


def as_vector(value: Any, n: int, name: str) -> np.ndarray:
    """A finite real (n,) vector of km / km/s components below 1e100 in magnitude (the OD wording)."""
    if isinstance(value, (str, bytes)):
        raise TypeError(f"{name}: must be a sequence of {n} numbers, got {type(value).__name__}")
    a = as_real_array(value, name, shape=(n,))
    # predict(x = 1e300) returned a NaN range: r^2 overflowed
    return check_magnitude(a, name, 1e100, "its square overflows double precision (hint: check the units)",
                           subject="every component", detail="km, km/s")


def as_series(value: Any, name: str) -> np.ndarray:
    """A real 1-D array (a scalar becomes one entry); ``"<name>: must be one-dimensional"`` otherwise."""
    a = np.atleast_1d(as_real_array(value, name, finite=False))
    if a.ndim != 1:
        raise ValueError(f"{name}: must be one-dimensional, got shape {a.shape}")
    return a


def as_float_array(value: Any, name: str) -> np.ndarray:
    """A float64 copy of a real array, in the propagation wording: ``"<name>: must be an array of real
    numbers"`` / ``"must be real, got complex dtype"`` (TypeError); a ragged or object input is a
    ValueError."""
    if isinstance(value, (str, bytes)):
        raise TypeError(f"{name}: must be an array of real numbers, got {type(value).__name__}")
    try:
        arr = np.asarray(value)
    except Exception as e:  # ragged nested sequences and the like
        raise ValueError(f"{name}: cannot be read as an array ({e})") from None
    if arr.dtype == object:
        raise ValueError(f"{name}: must be a regular array of real numbers (got a ragged or object array)")
    if np.iscomplexobj(arr):
        raise TypeError(f"{name}: must be real, got complex dtype {arr.dtype}")
    if arr.dtype == np.bool_ or arr.dtype.kind not in _REAL_KINDS:
        raise TypeError(f"{name}: must be an array of real numbers, got dtype {arr.dtype}")
    return arr.astype(np.float64)


def as_finite_positive(value: Any, name: str, *, positive: bool = True) -> float:
    """A finite float, > 0 when ``positive``: ``"<name>: must be finite and > 0, got ..."``."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise TypeError(f"{name}: must be a real number, got {type(value).__name__}")
    v = float(value)
    if not np.isfinite(v) or (positive and v <= 0.0):
        raise ValueError(f"{name}: must be finite and > 0, got {value!r}")
    return v


# ----------------------------------------------------------------------------- files
class FileFormatError(ValueError):
    """A file's content breaks its format: raised by every satgnc file reader (CSV, TDM, TOML).

    A subclass of ``ValueError``. ``str(err)`` reads ``"<path>:<line>: <message>"`` (``"<path>:
    <message>"`` when no single line is at fault). Attributes: ``path`` (:class:`pathlib.Path`),
    ``line`` (1-based int or ``None``), ``key`` (the keyword, TOML key or CSV column at fault, or
    ``None``) and ``reason`` (the message without the location)."""

    def __init__(self, path, line: int | None, reason: str, key: str | None = None):
        self.path = pathlib.Path(path)
        self.line = line
        self.key = key
        self.reason = reason
        where = f"{self.path}:{line}" if line is not None else f"{self.path}"
        super().__init__(f"{where}: {reason}")

    def __reduce__(self):  # picklable (multiprocessing sweeps)
        return (type(self), (self.path, self.line, self.reason, self.key))


FileFormatError.__module__ = "satgnc"


def did_you_mean(word: str, choices, fmt: str = "'{}'") -> str:
    """`` (did you mean 'x'?)`` for the closest of ``choices`` (difflib), or ``""``."""
    close = difflib.get_close_matches(word, list(choices), n=1, cutoff=0.6)
    if not close:
        close = [c for c in choices if c.lower() == word.lower()]
    return f" (did you mean {fmt.format(close[0])}?)" if close else ""


def read_text_file(path: Any, name: str = "path") -> tuple[pathlib.Path, str]:
    """``(Path, text)`` of a text file, or a clear error naming the file.

    UTF-8 with or without a byte-order mark, or UTF-16 with its mark; CRLF and CR line ends are left
    to ``str.splitlines``. A missing file is ``FileNotFoundError``, a directory
    ``IsADirectoryError``, a binary file or undecodable bytes a :class:`FileFormatError` with the
    line of the first bad byte."""
    if isinstance(path, bool) or not isinstance(path, (str, os.PathLike)):
        raise TypeError(f"{name}: must be a file path (str or os.PathLike), got {_describe(path)}")
    p = pathlib.Path(path)
    if str(path) == "":
        raise ValueError(f"{name}: must not be empty")
    if p.is_dir():
        raise IsADirectoryError(f"{name}: {p} is a directory, not a file")
    if not p.exists():
        raise FileNotFoundError(f"{name}: {p} does not exist")
    data = p.read_bytes()
    if data.startswith((b"\xff\xfe", b"\xfe\xff")):
        try:
            return p, data.decode("utf-16")
        except UnicodeDecodeError:
            raise FileFormatError(p, None, "not valid UTF-16 text after its byte-order mark") from None
    if data.startswith(b"\xef\xbb\xbf"):
        data = data[3:]
    nul = data.find(b"\x00")
    if nul >= 0:
        line = data.count(b"\n", 0, nul) + 1
        raise FileFormatError(p, line, "binary file (NUL byte), expected UTF-8 text")
    try:
        return p, data.decode("utf-8")
    except UnicodeDecodeError as e:
        line = data.count(b"\n", 0, e.start) + 1
        col = e.start - (data.rfind(b"\n", 0, e.start) + 1) + 1
        raise FileFormatError(
            p, line, f"not UTF-8 text: byte 0x{data[e.start]:02x} at column {col} "
            "(hint: save the file as UTF-8)"
        ) from None


# ----------------------------------------------------------------------------- TOML
def load_toml(path: Any, name: str = "path") -> tuple[pathlib.Path, str, dict]:
    """``(Path, text, data)`` of a TOML file; a syntax error is a :class:`FileFormatError` with the
    parser's line."""
    try:
        import tomllib  # Python >= 3.11
    except ModuleNotFoundError:  # pragma: no cover - Python 3.9/3.10
        try:
            import tomli as tomllib
        except ModuleNotFoundError as e:
            raise ModuleNotFoundError("reading TOML on Python < 3.11 needs the 'tomli' package") from e
    p, text = read_text_file(path, name)
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        msg = str(e)
        m = re.search(r"\(at line (\d+), column \d+\)", msg)
        line = int(m.group(1)) if m else None
        reason = re.sub(r"\s*\(at line \d+, column \d+\)", "", msg) if m else msg
        raise FileFormatError(p, line, f"TOML syntax: {reason}") from None
    return p, text, data


_HEADER = re.compile(r"^\s*\[\[?\s*([^\]]+?)\s*\]\]?\s*(#.*)?$")


def _toml_section_of_lines(text: str):
    """Yield (line number, section name or '', stripped line) for each line of a TOML text."""
    section = ""
    for i, raw in enumerate(text.splitlines(), start=1):
        m = _HEADER.match(raw)
        if m:
            section = ".".join(part.strip().strip('"').strip("'") for part in m.group(1).split("."))
            yield i, section, None
            continue
        yield i, section, raw.strip()


def toml_line(text: str, section: str, key: str | None = None) -> int | None:
    """Best-effort line of ``key`` in ``[section]`` (or of the section header when ``key`` is
    None) in a TOML text, for error messages; None when not found (dotted or inline keys)."""
    keyre = None if key is None else re.compile(rf"^[\"']?{re.escape(key)}[\"']?\s*=")
    for i, sec, stripped in _toml_section_of_lines(text):
        if sec != section:
            continue
        if key is None and stripped is None:
            return i
        if keyre is not None and stripped is not None and keyre.match(stripped):
            return i
    return None


@dataclasses.dataclass(frozen=True)
class Key:
    """One key of a strict TOML schema.

    ``kind``: "number" (float or integer, never boolean), "integer", "bool", "string" or "vector"
    (an array of ``length`` numbers). ``required`` keys without a ``default`` must be present.
    ``positive`` / ``nonnegative`` / ``low`` check numbers and vector entries; ``choices`` strings;
    ``nonzero`` vectors. ``unit`` is shown in messages."""

    kind: str
    required: bool = True
    default: Any = None
    positive: bool = False
    nonnegative: bool = False
    low: float | None = None
    high: float | None = None
    length: int | None = None
    choices: tuple[str, ...] | None = None
    nonzero: bool = False
    unit: str = ""
    #: vectors only: False lets entries be +-inf (a missing bound); NaN is always refused
    finite: bool = True


_KIND_TEXT = {
    "number": "a number",
    "integer": "an integer",
    "bool": "true or false",
    "string": "a string",
    "vector": "an array of {n} numbers",
}


def _toml_type(v: Any) -> str:
    if isinstance(v, bool):
        return f"boolean {str(v).lower()}"
    if isinstance(v, int):
        return f"integer {v}"
    if isinstance(v, float):
        return f"float {v!r}"
    if isinstance(v, str):
        return f"string {v!r}"
    if isinstance(v, list):
        return f"array of {len(v)}"
    if isinstance(v, dict):
        return "table"
    return type(v).__name__  # dates and times


def _is_toml_number(v: Any) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def _check_number(v: Any, spec: Key, fail) -> float:
    if spec.positive and not v > 0:
        fail(f"must be > 0, got {v!r}")
    if spec.nonnegative and not v >= 0:
        fail(f"must be >= 0, got {v!r}")
    if spec.low is not None and v < spec.low:
        fail(f"must be >= {spec.low}, got {v!r}")
    if spec.high is not None and v > spec.high:
        fail(f"must be <= {spec.high}, got {v!r}")
    return v


def check_toml_table(
    table: Any,
    schema: Mapping[str, Key],
    section: str,
    path: pathlib.Path,
    text: str = "",
) -> dict:
    """Check one TOML table against ``schema`` and return ``{key: value}`` with defaults filled in.

    Every error is a :class:`FileFormatError` naming the key and its section: an unknown key (with a
    "did you mean" suggestion), a missing required key, a wrong type (a boolean is never a number, a
    float never an integer, a string never a boolean) or a value out of range."""
    sec_text = f"[{section}]" if section else "the top level"
    if not isinstance(table, dict):
        parent, _, leaf = section.rpartition(".")
        line = (toml_line(text, section) or toml_line(text, parent, leaf)) if text else None
        raise FileFormatError(
            path, line, f"{section}: must be a table [{section}], got {_toml_type(table)}", key=section
        )
    out = {}
    for key in table:
        if key not in schema:
            hint = did_you_mean(key, schema)
            allowed = ", ".join(schema)
            raise FileFormatError(
                path, toml_line(text, section, key) if text else None,
                f"unknown key '{key}' in section {sec_text}{hint}; allowed keys: {allowed}", key=key,
            )
    for key, spec in schema.items():
        line = toml_line(text, section, key) if text else None

        def fail(rule: str, key=key, line=line, spec=spec) -> None:
            unit = f" ({spec.unit})" if spec.unit else ""
            raise FileFormatError(path, line, f"key '{key}' in section {sec_text}{unit}: {rule}", key=key)

        if key not in table:
            if spec.required and spec.default is None:
                raise FileFormatError(
                    path, toml_line(text, section) if text and section else None,
                    f"missing key '{key}' in section {sec_text}"
                    + (f" ({spec.unit})" if spec.unit else ""),
                    key=key,
                )
            out[key] = spec.default
            continue
        v = table[key]
        expected = _KIND_TEXT[spec.kind].format(n=spec.length)
        wrong = f"expected {expected}, got {_toml_type(v)}"
        if spec.kind == "number":
            if isinstance(v, bool) or not isinstance(v, (int, float)):
                fail(wrong)
            if not math.isfinite(v):
                fail(f"must be finite, got {v!r}")
            out[key] = _check_number(float(v), spec, fail)
        elif spec.kind == "integer":
            if isinstance(v, bool) or not isinstance(v, int):
                fail(wrong + (" (an integer count is never rounded)" if isinstance(v, float) else ""))
            out[key] = int(_check_number(v, spec, fail))
        elif spec.kind == "bool":
            if not isinstance(v, bool):
                hint = " (hint: write true or false without quotes)" if isinstance(v, str) else ""
                fail(wrong + hint)
            out[key] = v
        elif spec.kind == "string":
            if not isinstance(v, str):
                fail(wrong)
            if spec.choices is not None and v not in spec.choices:
                fail(f"must be one of {list(spec.choices)}, got {v!r}{did_you_mean(v, spec.choices)}")
            out[key] = v
        elif spec.kind == "vector":
            if not isinstance(v, list) or not all(_is_toml_number(e) for e in v):
                fail(wrong)
            if spec.length is not None and len(v) != spec.length:
                fail(wrong)
            for e in v:
                if not math.isfinite(e) and (spec.finite or math.isnan(e)):
                    fail(f"must be finite, got {v!r}" if spec.finite else f"must not hold nan, got {v!r}")
                _check_number(e, spec, fail)
            if spec.nonzero and not any(e != 0 for e in v):
                fail("must not be all zero")
            out[key] = [float(e) for e in v]
        else:  # pragma: no cover - schema bug
            raise AssertionError(spec.kind)
    return out


# ----------------------------------------------------------------------------- compiled names
# pybind11 converts anything numpy can cast (complex -> real with a ComplexWarning, True -> 1.0) and
# answers a wrong type with a dump of every overload's signature. ``harden_module`` wraps every
# function, method, constructor and settings field of the compiled module once at import, so that
# (1) a complex / boolean / object / string value for a numeric parameter is a TypeError naming it,
# (2) a bool for a number, NaN for a settings field, or an int out of the engine's range is refused
# naming the field, and (3) any remaining pybind11 "incompatible arguments" error is rewritten as
# "name: must be <type>, got <value>". Correct calls pay a few isinstance checks.

_INCOMPATIBLE = ("incompatible function arguments", "incompatible constructor arguments")


def _split_top(text: str) -> list[str]:
    """Split ``text`` at commas outside brackets and quotes."""
    out, depth, cur, quote = [], 0, [], ""
    for ch in text:
        if quote:
            cur.append(ch)
            if ch == quote:
                quote = ""
            continue
        if ch in "\"'":
            quote = ch
        elif ch in "([{":
            depth += 1
        elif ch in ")]}":
            depth -= 1
        elif ch == "," and depth == 0:
            out.append("".join(cur).strip())
            cur = []
            continue
        cur.append(ch)
    if "".join(cur).strip():
        out.append("".join(cur).strip())
    return out


def _parse_signature(line: str) -> list[tuple[str, str, bool]]:
    """[(name, annotation, has_default)] from a pybind11 signature line ``f(a: int, b: float = 1.0)``."""
    start = line.find("(")
    if start < 0:
        return []
    depth, end = 0, -1
    for i in range(start, len(line)):
        if line[i] in "([{":
            depth += 1
        elif line[i] in ")]}":
            depth -= 1
            if depth == 0:
                end = i
                break
    params = []
    for part in _split_top(line[start + 1:end]):
        if part in ("*", "/") or part.startswith("*"):
            continue
        name, _, rest = part.partition(":")
        annot, eq, _default = rest.partition("=")
        params.append((name.strip(), annot.strip(), bool(eq)))
    return params


@functools.cache  # called on every hardened call; cw_discretize spent a third of its time here
def _kind(annot: str) -> str:
    a = annot.replace("typing.", "")
    if a.startswith("Optional[") or a.endswith("| None"):
        a = a.removeprefix("Optional[").removesuffix("]").removesuffix("| None").strip()
    if "NDArray" in a or "numpy" in a or a.startswith(("list[float", "list[Supports", "Sequence[Supports",
                                                        "collections.abc.Sequence[Supports")):
        return "array"
    if a.startswith(("list[", "tuple[", "Sequence[", "collections.abc.Sequence[", "dict[")):
        return "other"  # a container of ints (e.g. SpkEphemeris pairs) is not an int
    if a in ("bool",):
        return "bool"
    if "SupportsFloat" in a or a == "float":
        return "float"
    if "SupportsInt" in a or a == "int":
        return "int"
    if a == "str":
        return "str"
    return "other"


def _check_param(name: str, annot: str, value: Any, *, field: bool = False) -> None:
    """Raise TypeError / ValueError naming ``name`` when ``value`` cannot be a ``annot``."""
    if value is None and ("Optional" in annot or "None" in annot):
        return
    kind = _kind(annot)
    if kind == "float" and type(value) is float and not field:  # fast path of the common case
        return
    if kind == "array":
        if isinstance(value, np.ndarray):
            if value.dtype.kind not in _REAL_KINDS:
                as_real_array(value, name, finite=False)  # raises the uniform TypeError
        elif isinstance(value, (list, tuple)):
            if value and isinstance(value[0], (list, tuple, np.ndarray)):
                # nested: a matrix as lists, or a list of matrices whose shapes may differ (H_j)
                for item in value:
                    as_real_array(item, name, finite=False)
            elif any(not isinstance(x, numbers.Real) or isinstance(x, (bool, np.bool_)) for x in value):
                as_real_array(value, name, finite=False)
        elif isinstance(value, (str, bytes, bool, np.bool_, complex)):
            as_real_array(value, name, finite=False)
    elif kind == "float":
        if isinstance(value, np.ndarray) and value.ndim == 0:
            value = value[()]
        if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
            raise TypeError(f"{name}: must be a real number, got {_describe(value)}")
        if field and math.isnan(float(value)):
            raise ValueError(f"{name}: must not be NaN")
    elif kind == "int":
        as_int(value, name)
    elif kind == "bool":
        as_bool(value, name)
    elif kind == "str":
        if not isinstance(value, str):
            raise TypeError(f"{name}: must be a string, got {_describe(value)}")


def _fixed_shape(annot: str) -> tuple[int | None, ...] | None:
    """(12, 1) from an Eigen annotation '... "[12, 1]"' (None for a free dimension), else None."""
    m = re.search(r'"\[([0-9mn]+)(?:, ([0-9mn]+))?\]"', annot)
    if not m:
        return None
    return tuple(int(d) if d.isdigit() else None for d in m.groups() if d is not None)


def _short(annot: str) -> str:
    kind = _kind(annot)
    return {"array": "a real numeric array", "float": "a real number", "int": "an integer",
            "bool": "a bool", "str": "a string"}.get(kind, annot.replace("satgnc._satgnc.", ""))


def _diagnose(qualname: str, message: str, args: tuple, kwargs: dict) -> str:
    """Turn a pybind11 overload dump into 'name: must be ..., got ...' for the first wrong argument."""
    lines = [ln.strip() for ln in message.splitlines() if re.match(r"\s*\d+\.\s", ln)]
    sigs = [_parse_signature(ln.split(".", 1)[1]) for ln in lines] or [[]]
    # Methods list self; constructors do not, but are called with the new instance first.
    is_method = (bool(sigs[0]) and sigs[0][0][0] == "self") or "constructor" in message
    npos = len(args) - 1 if is_method and args else len(args)

    def fits(sig: list) -> bool:  # the call's shape matches this overload (names, counts)
        own = [p for p in sig if p[0] != "self"]
        required = sum(not p[2] for p in own)
        return (all(k in {p[0] for p in own} for k in kwargs) and npos <= len(own)
                and required <= npos + len(kwargs))

    params = next((sig for sig in sigs if fits(sig)), sigs[0])
    named = [p for p in params if p[0] != "self"]
    pos = list(args[1:] if is_method and args else args)
    names = [p[0] for p in named]
    for key in kwargs:
        if key not in names:
            return f"{key}: unknown argument of {qualname} (accepted: {', '.join(names)})"
    bound = dict(zip(names, pos))
    if len(pos) > len(named):
        return f"{qualname}: takes {len(named)} argument(s) ({', '.join(names)}), got {len(pos)}"
    bound.update(kwargs)
    for pname, annot, has_default in named:
        if pname not in bound:
            if not has_default:
                return f"{pname}: required argument of {qualname} is missing"
            continue
        value = bound[pname]
        try:
            _check_param(pname, annot, value)
        except (TypeError, ValueError) as e:
            return str(e)
        if _kind(annot) == "int":
            return (f"{pname}: out of the engine's integer range (a count, size or seed must be >= 0 and "
                    f"fit in 32 or 64 bits), got {value!r}")
        shape = None if annot.startswith(("list[", "collections.abc.Sequence[")) else _fixed_shape(annot)
        if shape is not None:
            got = np.shape(value)
            flat = got if len(got) != 2 or got[1] != 1 else (got[0],)
            want = shape[:-1] if len(shape) == 2 and shape[-1] == 1 else shape
            if len(flat) != len(want) or any(w is not None and w != f for w, f in zip(want, flat)):
                dims = ", ".join("n" if d is None else str(d) for d in want)
                return f"{pname}: must have shape ({dims}{',' if len(want) == 1 else ''}), got {got}"
    for pname, annot, _ in named:
        if pname in bound and _kind(annot) == "other":
            if type(bound[pname]).__name__ == annot.rsplit(".", 1)[-1]:
                continue  # the right class: another argument is at fault
            return f"{pname}: must be {_short(annot)}, got {_describe(bound[pname])}"
    return f"{qualname}: arguments do not match its signature {lines[0] if lines else ''}"


def _out_of_memory(qualname: str, params: list, args: tuple, kwargs: dict) -> str:
    """'horizon: 1000000000 is too large ...' naming the largest integer argument (a size) of the call."""
    bound = dict(zip([p[0] for p in params], args))
    bound.update(kwargs)
    sizes = [(v, k) for k, v in bound.items() if isinstance(v, numbers.Integral) and not isinstance(v, bool)]
    for k, v in bound.items():  # sizes of problem structs (e.g. NonlinearL1Problem.horizon)
        for attr in ("horizon", "n", "steps", "max_steps"):
            val = getattr(v, attr, None)
            if isinstance(val, numbers.Integral) and not isinstance(val, bool):
                sizes.append((val, f"{k}.{attr}"))
    if sizes:
        value, name = max(sizes)
        return (f"{name}: {value} is too large: {qualname} could not allocate the memory this size needs "
                f"(std::bad_alloc)")
    return f"{qualname}: the engine could not allocate the memory these arguments need (std::bad_alloc)"


def _wrap_callable(f: Any, qualname: str) -> Any:
    import functools

    doc = (getattr(f, "__doc__", None) or "").strip().splitlines()
    params = _parse_signature(doc[0]) if doc else []
    # An overloaded function (e.g. AdmmSolver(A, B, ...) beside AdmmSolver(problem, settings)) lists
    # its signatures as "1. name(...)", "2. ..."; a call is checked against the first one it fits.
    overloads = [_parse_signature(ln.split(".", 1)[1]) for ln in doc[1:] if re.match(r"\d+\.\s", ln)] \
        if len(doc) > 1 and doc[1].strip() == "Overloaded function." else []

    def checks_of(sig: list) -> tuple[list, dict]:
        # pybind11 accepts True for a float or an int, 1 for a bool and complex arrays for real ones:
        # check those parameters before the call (the rest fail inside pybind11 and are diagnosed below).
        chk = [(i, p[0], p[1]) for i, p in enumerate(sig) if _kind(p[1]) in ("array", "float", "int", "bool")]
        return chk, {name: annot for _, name, annot in chk}

    checked, by_name = checks_of(params)
    alternatives = [(sum(not p[2] for p in sig), len(sig), {p[0] for p in sig}, *checks_of(sig))
                    for sig in overloads]

    @functools.wraps(f)
    def wrapper(*args, **kwargs):
        chk, names = checked, by_name
        for required, n, accepted, c, b in alternatives:
            if required <= len(args) + len(kwargs) and len(args) <= n and all(k in accepted for k in kwargs):
                chk, names = c, b
                break
        for i, name, annot in chk:
            if i < len(args):
                _check_param(name, annot, args[i])
        if kwargs:
            for key, value in kwargs.items():
                annot = names.get(key)
                if annot is not None:
                    _check_param(key, annot, value)
        try:
            return f(*args, **kwargs)
        except MemoryError:
            raise ValueError(_out_of_memory(qualname, params, args, kwargs)) from None
        except TypeError as e:
            if not any(s in str(e) for s in _INCOMPATIBLE):
                raise
            msg = _diagnose(qualname, str(e), args, kwargs)
            kind = ValueError if ("out of the engine's integer range" in msg or "must have shape" in msg) \
                else TypeError
            raise kind(msg) from None

    wrapper.__satgnc_hardened__ = True
    return wrapper


def _harden_property(cls: type, name: str, prop: property) -> property:
    doc = (getattr(prop.fset, "__doc__", None) or "").strip().splitlines()
    params = _parse_signature(doc[0]) if doc else []
    annot = params[-1][1] if params else ""
    fset, fget = prop.fset, prop.fget
    label = f"{name}"
    enum_type = None
    if _kind(annot) == "other" and annot.startswith("satgnc._satgnc."):
        enum_type = getattr(_compiled_module, annot.rsplit(".", 1)[1], None)
        if enum_type is not None and not hasattr(enum_type, "__members__"):
            enum_type = None

    def setter(self, value):
        if enum_type is not None and isinstance(value, str):
            if value not in enum_type.__members__:
                raise ValueError(f"{label}: must be one of {list(enum_type.__members__)}, got {value!r}")
            value = enum_type.__members__[value]
        elif enum_type is not None and not isinstance(value, enum_type):
            raise TypeError(f"{label}: must be one of {list(enum_type.__members__)} "
                            f"({enum_type.__name__}), got {_describe(value)}")
        _check_param(label, annot, value, field=True)
        old = fget(self) if fget is not None else None
        try:
            fset(self, value)
        except TypeError as e:
            if not any(s in str(e) for s in _INCOMPATIBLE):
                raise
            if _kind(annot) == "int":
                raise ValueError(f"{label}: out of the engine's integer range (a count, size or seed must be "
                                 f">= 0 and fit in 32 or 64 bits), got {value!r}") from None
            raise TypeError(f"{label}: must be {_short(annot)}, got {_describe(value)}") from None
        # A rule of the class's own validate() about this field (e.g. "max_iterations: must be > 0")
        # fails at the assignment, and the old value stays; rules about other fields wait for setup.
        validate = getattr(self, "validate", None)
        if callable(validate) and fget is not None:
            try:
                validate()
            except ValueError as e:
                if str(e).startswith((f"{name}:", f"{name} ", f"settings.{name}:")):
                    fset(self, old)
                    raise

    return property(fget, setter, prop.fdel, prop.__doc__)


_compiled_module: Any = None


def harden_module(module: Any) -> None:
    """Wrap the compiled module's functions, methods, constructors and settings fields (idempotent)."""
    global _compiled_module
    if getattr(module, "__satgnc_hardened__", False):
        return
    _compiled_module = module
    for name, obj in list(vars(module).items()):
        if name.startswith("__"):
            continue
        if isinstance(obj, type):
            if hasattr(obj, "__members__"):  # pybind11 enums
                continue
            for attr, value in list(vars(obj).items()):
                if attr.startswith("__") and attr != "__init__":
                    continue
                if isinstance(value, property):
                    if value.fset is not None:
                        setattr(obj, attr, _harden_property(obj, attr, value))
                elif isinstance(value, staticmethod):
                    setattr(obj, attr, staticmethod(_wrap_callable(value.__func__, f"{obj.__name__}.{attr}")))
                elif callable(value) and type(value).__name__ in ("instancemethod",
                                                                  "builtin_function_or_method"):
                    setattr(obj, attr, _wrap_callable(value, f"{obj.__name__}.{attr}"))
        elif type(obj).__name__ == "builtin_function_or_method":
            setattr(module, name, _wrap_callable(obj, name))
    module.__satgnc_hardened__ = True

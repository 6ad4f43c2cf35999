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
    "as_int",
    "as_real",
    "as_real_array",
    "check_toml_table",
    "did_you_mean",
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
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
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
                if not math.isfinite(e):
                    fail(f"must be finite, got {v!r}")
                _check_number(e, spec, fail)
            if spec.nonzero and not any(e != 0 for e in v):
                fail("must not be all zero")
            out[key] = [float(e) for e in v]
        else:  # pragma: no cover - schema bug
            raise AssertionError(spec.kind)
    return out

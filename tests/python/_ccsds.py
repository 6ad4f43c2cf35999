"""Shared fixtures of the CCSDS file tests (test_io.py, test_io_xml.py): the standards' example files, a
field-by-field model comparison with tolerance 0, and an estimated LEO trajectory written from Python."""

from __future__ import annotations

import dataclasses
import pathlib

import numpy as np
from satgnc import io

DATA = pathlib.Path(__file__).resolve().parent.parent / "data" / "ccsds"


def assert_same(a: object, b: object, where: str = "") -> None:
    """Field-by-field equality of two models (arrays: exact, NaN == NaN)."""
    assert type(a) is type(b), where
    if dataclasses.is_dataclass(a):
        for f in dataclasses.fields(a):
            assert_same(getattr(a, f.name), getattr(b, f.name), f"{where}.{f.name}")
    elif isinstance(a, np.ndarray):
        np.testing.assert_array_equal(a, b, err_msg=where)  # exact (tolerance 0)
    elif isinstance(a, tuple):
        assert len(a) == len(b), where
        for i, (x, y) in enumerate(zip(a, b)):
            assert_same(x, y, f"{where}[{i}]")
    else:
        assert a == b, f"{where}: {a!r} != {b!r}"


def leo_metadata(start: str, stop: str, **extra: object) -> io.OemMetadata:
    """OEM metadata of the test satellite LEO-1 (GCRF, UTC) over [start, stop]."""
    return io.OemMetadata(
        object_name="LEO-1",
        object_id="2026-001A",
        center_name="EARTH",
        ref_frame="GCRF",
        time_system="UTC",
        start_time=start,
        stop_time=stop,
        **extra,  # type: ignore[arg-type]
    )


def estimated_oem(seed: int, day: str, n_cov: int, no_acceleration_row: int) -> io.Oem:
    """An estimated trajectory: 4 states (km, km/s) one minute apart on 2026-12-`day`, accelerations
    except on one line (NaN), and `n_cov` symmetric covariances (km^2...) in RTN."""
    rng = np.random.default_rng(seed)
    states = rng.normal(size=(4, 6)) * [7000, 7000, 7000, 7.5, 7.5, 7.5]
    acc = rng.normal(size=(4, 3)) * 1e-3
    acc[no_acceleration_row] = np.nan  # no acceleration on that line
    covs = []
    for i in range(n_cov):
        a = rng.normal(size=(6, 6))
        c = a @ a.T * 1e-6
        covs.append(
            io.OemCovariance(epoch=f"2026-12-{day}T00:0{i}:00", matrix=(c + c.T) / 2, cov_ref_frame="RTN")
        )
    meta = leo_metadata(
        f"2026-12-{day}T00:00:00", f"2026-12-{day}T00:03:00", interpolation="LAGRANGE", interpolation_degree=5
    )
    return io.Oem(
        header=io.Header(creation_date=f"2026-12-{day}T12:00:00", originator="SATGNC"),
        segments=(
            io.OemSegment(
                metadata=meta,
                epochs=tuple(f"2026-12-{day}T00:0{i}:00" for i in range(4)),
                states=states,
                accelerations=acc,
                covariances=tuple(covs),
            ),
        ),
    )


def two_way_tdm() -> io.Tdm:
    """Two-way range + Doppler + RADEC angles written from Python, values needing 17 digits."""
    meta = io.TdmMetadata(
        time_system="UTC",
        participants=("DSS-65", "SAT"),
        mode="SEQUENTIAL",
        path=(1, 2, 1),
        range_units="km",
        angle_type="RADEC",
        integration_interval=10.0,
        integration_ref="MIDDLE",
        other=(("CORRECTION_RANGE", "0.0"),),
        comments=("written by test_io",),
    )
    rng = np.random.default_rng(13)
    n = 12
    keywords = ("RANGE", "DOPPLER_INTEGRATED", "ANGLE_1", "ANGLE_2") * (n // 4)
    # two epochs before the leap second of 2016-12-31, then one inside it (23:59:60.5)
    epochs = tuple(
        f"2016-12-31T23:59:{58 + i // 4:02d}.25" if i < 8 else "2016-12-31T23:59:60.5" for i in range(n)
    )
    values = rng.normal(size=n) * np.array([1e4, 5.0, 100.0, 40.0] * (n // 4))
    seg = io.TdmSegment(metadata=meta, keywords=keywords, epochs=epochs, values=values)
    return io.Tdm(
        header=io.Header(creation_date="2026-12-02T00:00:00", originator="SATGNC", message_id="T-1"),
        segments=(seg,),
    )

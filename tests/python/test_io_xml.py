"""satgnc.io XML writers of OEM and OPM from Python (issue 13): format_oem_xml / format_opm_xml and
their write_* twins.

Checks: the standards' example files (tests/data/ccsds) and an estimated trajectory with accelerations
and covariances, written in XML and read back, equal the model field by field bit for bit (tolerance 0:
the writer prints the shortest text that reads back to the same double); writing the read-back model
gives the same text again; the XML and KVN forms read to the same model."""

from __future__ import annotations

import dataclasses
import pathlib

import numpy as np
import pytest
from satgnc import io

DATA = pathlib.Path(__file__).resolve().parents[1] / "data" / "ccsds"


def _assert_same(a: object, b: object, where: str = "") -> None:
    """Field-by-field equality of two models (arrays: exact, NaN == NaN)."""
    assert type(a) is type(b), where
    if dataclasses.is_dataclass(a):
        for f in dataclasses.fields(a):
            _assert_same(getattr(a, f.name), getattr(b, f.name), f"{where}.{f.name}")
    elif isinstance(a, np.ndarray):
        np.testing.assert_array_equal(a, b, err_msg=where)  # exact (tolerance 0)
    elif isinstance(a, tuple):
        assert len(a) == len(b), where
        for i, (x, y) in enumerate(zip(a, b)):
            _assert_same(x, y, f"{where}[{i}]")
    else:
        assert a == b, f"{where}: {a!r} != {b!r}"


def _estimated_oem() -> io.Oem:
    rng = np.random.default_rng(11)
    states = rng.normal(size=(4, 6)) * [7000, 7000, 7000, 7.5, 7.5, 7.5]
    acc = rng.normal(size=(4, 3)) * 1e-3
    acc[1] = np.nan  # no acceleration on that line
    covs = []
    for i in range(3):
        a = rng.normal(size=(6, 6))
        c = a @ a.T * 1e-6
        covs.append(
            io.OemCovariance(epoch=f"2026-12-03T00:0{i}:00", matrix=(c + c.T) / 2, cov_ref_frame="RTN")
        )
    meta = io.OemMetadata(
        object_name="LEO-1",
        object_id="2026-001A",
        center_name="EARTH",
        ref_frame="GCRF",
        time_system="UTC",
        start_time="2026-12-03T00:00:00",
        stop_time="2026-12-03T00:03:00",
        interpolation="LAGRANGE",
        interpolation_degree=5,
    )
    return io.Oem(
        header=io.Header(creation_date="2026-12-03T12:00:00", originator="SATGNC"),
        segments=(
            io.OemSegment(
                metadata=meta,
                epochs=tuple(f"2026-12-03T00:0{i}:00" for i in range(4)),
                states=states,
                accelerations=acc,
                covariances=tuple(covs),
            ),
        ),
    )


def test_oem_xml_round_trip_bit_for_bit(tmp_path: pathlib.Path) -> None:
    for name, model in (("mgs", io.read_oem(DATA / "oem_mgs.kvn")), ("est", _estimated_oem())):
        xml = io.format_oem_xml(model)
        assert xml.lstrip().startswith("<?xml") and "<oem" in xml and "<stateVector>" in xml
        back = io.parse_oem(xml, f"{name}.xml")
        _assert_same(back, model, name)
        assert io.format_oem_xml(back) == xml  # the text is a fixed point
        path = io.write_oem_xml(tmp_path / f"{name}.xml", model)
        assert path.read_text() == xml
        _assert_same(io.read_oem(path), model, f"{name} (file)")
        # KVN and XML carry the same model.
        _assert_same(io.parse_oem(io.format_oem(model)), io.parse_oem(xml), f"{name} kvn vs xml")
    est = io.format_oem_xml(_estimated_oem())
    assert est.count("<covarianceMatrix>") == 3 and est.count("<stateVector>") == 4
    assert est.count("<X_DDOT") == 3  # the line without acceleration has none


def test_opm_xml_round_trip_bit_for_bit(tmp_path: pathlib.Path) -> None:
    names = ("opm_godzilla.kvn", "opm_eutelsat.kvn", "opm_osprey_cov.kvn")
    models = [io.read_opm(DATA / n) for n in names]
    c = models[2]
    models.append(
        dataclasses.replace(
            c,
            state=c.state / 7.0,
            time_system="TT",
            keplerian=io.OpmKeplerian(7000.0, 1e-3, 51.6, 10.0, 20.0, 398600.4418, mean_anomaly=1 / 3),
        )
    )
    for i, model in enumerate(models):
        xml = io.format_opm_xml(model)
        assert xml.lstrip().startswith("<?xml") and "<opm" in xml
        back = io.parse_opm(xml, f"opm{i}.xml")
        _assert_same(back, model, f"opm{i}")
        assert io.format_opm_xml(back) == xml
        path = io.write_opm_xml(tmp_path / f"opm{i}.xml", model)
        _assert_same(io.read_opm(path), model, f"opm{i} (file)")
        _assert_same(io.parse_opm(io.format_opm(model)), back, f"opm{i} kvn vs xml")
    eutelsat = io.format_opm_xml(models[1])
    assert eutelsat.count("<maneuverParameters>") == 2


def test_xml_writers_refuse_other_objects() -> None:
    with pytest.raises(TypeError, match="oem"):
        io.format_oem_xml("not an oem")  # type: ignore[arg-type]
    with pytest.raises(TypeError, match="opm"):
        io.format_opm_xml(io.read_oem(DATA / "oem_mgs.kvn"))  # type: ignore[arg-type]

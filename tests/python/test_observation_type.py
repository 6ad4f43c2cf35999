"""Observations.type holds strings (issue 17 item 4: the docs promised strings, it held enums): an
ObservationType str enum that keeps scripts written against the MeasurementType enums working, with a
DeprecationWarning. Every assertion is exact (equality, types, warnings, file text)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from satgnc import od


def _table() -> od.Observations:
    return od.Observations([0.0, 10.0, 20.0], ["range", od.MeasurementType.range_rate, "range"],
                           [7000.0, 0.5, 7001.0], [1e-3, 1e-6, 1e-3], [0, 0, 1])


def test_type_holds_strings():
    obs = _table()
    assert obs.type == ["range", "range_rate", "range"]
    assert all(isinstance(k, str) and isinstance(k, od.ObservationType) for k in obs.type)
    assert [str(k) for k in obs.type] == ["range", "range_rate", "range"]
    assert f"{obs.type[1]}" == "range_rate" and f"{obs.type[0]:>6}" == " range"
    assert obs.type_names() == ["range", "range_rate", "range"]
    assert {"range": 1}[obs.type[0]] == 1  # hashes like its string
    assert list(np.array(obs.type)) == ["range", "range_rate", "range"]


def test_old_enum_idioms_still_work_with_a_deprecation_warning():
    obs = _table()
    with pytest.warns(DeprecationWarning, match="compare with 'range'"):
        assert obs.type[0] == od.MeasurementType.range
    with pytest.warns(DeprecationWarning):
        assert obs.type[1] != od.MeasurementType.range
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # none of these warn
        assert obs.type[0].name == od.MeasurementType.range.name == "range"
        assert int(obs.type[1]) == int(od.MeasurementType.range_rate)
        assert obs.type[1].measurement_type is od.MeasurementType.range_rate
        assert obs.type[0] != "range_rate"


def test_solvers_and_writers_take_the_string_types(tmp_path):
    obs = _table()
    ms = obs.measurements()  # the C++ Measurement takes the compiled enum: converted
    assert [m.type for m in ms] == [od.MeasurementType.range, od.MeasurementType.range_rate,
                                    od.MeasurementType.range]
    # od.predict takes an ObservationType like a string (range of a satellite 1000 km above a station
    # at rest on the x axis: exactly 1000 km).
    v, _ = od.predict(obs.type[0], [7378.0, 0, 0, 0, 7.5, 0], [6378.0, 0, 0, 0, 0, 0])
    assert v == 1000.0
    p = obs.write_csv(tmp_path / "obs.csv")
    assert p.read_text().splitlines()[1:3] == ["0.0,range,7000.0,0.001,0", "10.0,range_rate,0.5,1e-06,0"]
    back = od.read_csv(p)
    assert back.type == obs.type and isinstance(back.type[0], od.ObservationType)
    sub = obs.select([True, False, True])
    assert sub.type == ["range", "range"]


def test_unknown_type_is_refused_naming_it():
    with pytest.raises(ValueError, match="type"):
        od.Observations([0.0], ["angle"], [1.0], [1.0], [0])

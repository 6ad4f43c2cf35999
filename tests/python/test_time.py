"""satgnc.time: Epoch and TimeScale over ERFA (leap seconds, ISO-8601, scales, precision, bad input)."""

from __future__ import annotations

import pickle

import pytest
from satgnc.time import Epoch, TimeScale, parse, time_scale_from_name


def test_leap_second_2016_parse_format_and_count():
    # 2016-12-31T23:59:60.5 UTC = 2017-01-01T00:00:36.5 TAI; TAI-UTC 36 s before, 37 s after.
    leap = Epoch.parse("2016-12-31T23:59:60.5", "UTC")
    assert leap.to_iso("TAI", 3) == "2017-01-01T00:00:36.500"
    assert leap.to_iso("UTC", 1) == "2016-12-31T23:59:60.5"
    before, after = Epoch.parse("2016-12-31T23:59:59"), Epoch.parse("2017-01-01T00:00:00")
    assert after - before == 2.0  # exact: two SI seconds across the leap
    assert (before.tai_minus_utc(), after.tai_minus_utc()) == (36.0, 37.0)
    assert leap.calendar("UTC", 3) == (2016, 12, 31, 23, 59, 60.5)


def test_vallado_example_time_line_and_gps():
    # Vallado 4th ed. Example 3-7/3-14: 2004-04-06 07:51:28.386009 UTC -> TT 07:52:32.570009
    # (TAI-UTC 32 s), JD_TT 2453101.828154745 (printed to 1e-9 d).
    e = parse("2004-04-06T07:51:28.386009")
    assert e.to_iso(TimeScale.TT, 6) == "2004-04-06T07:52:32.570009"
    assert e.to_iso("gps", 6) == "2004-04-06T07:51:41.386009"  # GPS = TAI - 19 s
    jd1, jd2 = e.jd("TT")
    assert jd1 + jd2 == pytest.approx(2453101.828154745, abs=1e-9)
    assert abs(e.offset_from_tai("TDB") - 32.184) < 1.7e-3  # |TDB-TT| < 1.7 ms (eraDtdb amplitude)


def test_erfa_utctai_case_and_mjd_arithmetic():
    # t_erfa_c.c t_utctai: UTC 2453750.5 + 0.892100694 -> TAI 0.8924826384444444444 (1e-12 d).
    jd1, jd2 = Epoch.from_jd(2453750.5, 0.892100694, "UTC").jd("TAI")
    assert (jd1 - 2453750.5) + jd2 == pytest.approx(0.8924826384444444444, abs=1e-12)
    # An independent calendar check: MJD 59277 is 2021-03-04 and 05:06:07.25 is 18367.25 s.
    e = Epoch.from_calendar(2021, 3, 4, 5, 6, 7.25, scale="TT")
    assert e.mjd("TT") == pytest.approx(59277 + 18367.25 / 86400, abs=1e-10)  # one float MJD: ~1e-11 d


@pytest.mark.parametrize("scale", ["TAI", "TT", "UTC", "GPS", "TDB"])
def test_iso_round_trip_nanoseconds(scale):
    for text in ("2024-02-29T13:45:07.123456789", "1999-12-31T23:59:59.999999999"):
        assert Epoch.parse(text, scale).to_iso(scale, 9) == text  # exact: the epoch holds ~1e-16 s
    assert Epoch.parse("2024-060T13:45:07.5", scale) == Epoch.parse("2024-02-29T13:45:07.5", scale)


def test_precision_arithmetic_ordering_and_pickle():
    e = Epoch.parse("2049-11-30T17:00:00.3", "TAI")
    for dt in (1e-9, 0.1, 99999.999):
        assert (e + dt) - e == pytest.approx(dt, abs=2.3e-16 + dt * 2.3e-16)  # ulp of the fraction + of dt
    assert e < e + 1e-12 and e - 1e-12 < e and 5.0 + e == e + 5.0
    assert pickle.loads(pickle.dumps(e)) == e
    assert len({e, Epoch.from_tai_seconds(e.tai_whole, e.tai_fraction)}) == 1
    assert repr(Epoch()) == "Epoch('2000-01-01T12:00:00.000000000', 'TAI')"


def test_bad_input_names_argument_or_text():
    msg = r"^time_scale: unknown time system 'GMT' \(choices: TAI, TT, UTC, GPS, TDB\)$"
    with pytest.raises(ValueError, match=msg):
        time_scale_from_name("GMT")
    with pytest.raises(ValueError, match="EopTable"):
        Epoch.parse("2020-01-01T00:00:00", "UT1")
    with pytest.raises(ValueError, match=r"'2016-13-01T00:00:00'.*month: 13 not in 1..12"):
        Epoch.parse("2016-13-01T00:00:00")
    with pytest.raises(ValueError, match="hour must have 2 digits"):
        Epoch.parse("2016-01-01T1:00:00")
    with pytest.raises(ValueError, match="second: 60 is valid only at 23:59 of a UTC day that ends with a"):
        Epoch.parse("2016-12-30T23:59:60")
    with pytest.raises(ValueError, match="UTC is defined from 1960"):
        Epoch.from_calendar(1950, 1, 1)
    with pytest.raises(TypeError, match="scale: must be a TimeScale or a name"):
        Epoch.parse("2016-01-01T00:00:00", 3)
    with pytest.raises(TypeError, match="text: must be a str"):
        parse(20160101)
    with pytest.raises(ValueError, match="decimals: must be in 0..12"):
        Epoch().to_iso("TAI", 13)

"""satgnc.frames: EOP tables (sample files and astropy-iers-data), GCRS <-> ITRS (Vallado 3-14),
EME2000, IauEarthRotation, ground stations against an independent numpy construction, bad input."""

from __future__ import annotations

import math
import pathlib

import numpy as np
import pytest
import satgnc
from satgnc import frames
from satgnc.time import Epoch

EOP_DIR = pathlib.Path(__file__).resolve().parents[1] / "data" / "eop"
FINALS = EOP_DIR / "finals2000A_2016-12.txt"
C04 = EOP_DIR / "eopc04_2016-12.txt"


def test_sample_tables_read_and_agree():
    fin, c04 = frames.load_eop(FINALS), frames.load_eop(C04)
    assert len(fin) == len(c04) == 62
    assert set(fin.sources) == {"bulletin_b"} and set(c04.sources) == {"c04"}
    assert fin.mjd[0] == 57723.0 and fin.mjd[-1] == 57784.0
    # Row 2016-12-31, Bulletin B: x 0.081318", UT1-UTC -0.4077600 s (the file's digits).
    assert fin.xp[30] == 0.081318 and fin.ut1_utc[30] == -0.40776
    # C04 and Bulletin B agree to < 0.5 mas and < 0.1 ms (measured 0.15 mas, 0.02 ms).
    e = Epoch.parse("2016-12-05T06:00:00")
    a, b = fin.at(e), c04.at(e)
    assert abs(a.xp - b.xp) < 0.5e-3 and abs(a.ut1_utc - b.ut1_utc) < 1e-4
    # UT1-UTC jumps by 1 s at the leap second (interpolated as UT1-TAI).
    jump = fin.ut1_minus_utc(Epoch.parse("2017-01-01T00:00:00.5")) - fin.ut1_minus_utc(
        Epoch.parse("2016-12-31T23:59:59.5"))
    assert jump == pytest.approx(1.0, abs=1e-5)


def test_default_eop_from_astropy_iers_data():
    eop = frames.default_eop()
    assert frames.default_eop() is eop  # cached
    assert frames.default_eop_path().name == "finals2000A.all"
    assert len(eop) > 15000 and eop.mjd[0] == 41684.0  # daily since 1973-01-02
    # On the sample's days the full table holds the same Bulletin B values.
    e = Epoch.parse("2016-12-31T00:00:00")
    assert eop.at(e).xp == pytest.approx(0.081318, abs=1e-15)
    assert eop.covers(e) and "bulletin_a_prediction" in eop.sources


def test_out_of_range_policies_and_file_errors(tmp_path):
    fin = frames.load_eop(FINALS)
    late = Epoch.parse("2017-02-15T00:00:00")
    span = r"\(MJD 57723 \.\. 57784 = 2016-12-01 \.\. 2017-01-31 UTC\)"
    where = r"epoch: 2017-02-15T00:00:00.000 UTC is outside the EOP table "
    with pytest.raises(ValueError, match=where + span):
        fin.at(late)
    assert fin.with_policy("hold_last").at(late).xp == fin.xp[-1]
    assert frames.load_eop(FINALS, policy="zero").at(late).ut1_utc == 0.0
    lines = FINALS.read_text().splitlines()
    bad = tmp_path / "bad.all"
    bad.write_text("\n".join(lines[:3] + [lines[3][:7] + "57726.x0" + lines[3][15:]]) + "\n")
    msg = r"bad.all:4: columns 8-15 \(MJD\): '57726.x0' is not a number"
    with pytest.raises(satgnc.FileFormatError, match=msg) as ei:
        frames.load_eop(bad)
    assert ei.value.line == 4
    with pytest.raises(FileNotFoundError, match="does not exist"):
        frames.load_eop(tmp_path / "missing.all")
    with pytest.raises(ValueError, match=r"policy: must be one of \['error', 'hold_last', 'zero'\]"):
        frames.load_eop(FINALS, policy="clamp")


def test_vallado_example_3_14_itrf_to_gcrf():
    # Vallado 4th ed. Example 3-14 with its EOP; GCRF of Table 3-6 (IAU-2006/2000 CIO), as quoted by
    # public reproductions. satgnc (IERS 2010: two-part JD, IAU 2006/2000A) is 9.03 mm / 4.4 um/s away, fully
    # explained in test_frames_vallado.py: 8.5 mm is the book's JD_UT1 held in one double (14.69 us late),
    # 0.85 mm its IAU 2000A series; with both emulated the table holds to 6.4e-8 km (printed 1e-7 km).
    eop = frames.EopTable([53101.0, 53102.0], [-0.140682] * 2, [0.333309] * 2, [-0.4399619] * 2,
                          lod=[0.0015563] * 2, dx=[-0.000205] * 2, dy=[-0.000136] * 2)
    assert repr(eop) == "<EopTable 2 rows, MJD 53101 .. 53102, policy error>"
    bare = frames.EopTable([53101.0, 53102.0], [0.1, 0.1], [0.2, 0.2], [0.3, 0.3])  # lod, dx, dy: zeros
    assert bare.at(Epoch.parse("2004-04-06")).dx == 0.0
    e = Epoch.parse("2004-04-06T07:51:28.386009")
    x_itrf = np.array([-1033.4793830, 7901.2952754, 6380.3565958, -3.225636520, -2.872451450, 5.531924446])
    g = frames.itrs_to_gcrs(x_itrf, e, eop)
    book = np.array([5102.50895290, 6123.01139910, 6378.13693380, -4.7432201610, 0.7905364950, 5.5337557240])
    assert np.linalg.norm(g[:3] - book[:3]) == pytest.approx(9.028e-6, abs=2e-9)  # km: the explained gap
    assert np.linalg.norm(g[3:] - book[3:]) == pytest.approx(4.439e-9, abs=2e-12)  # km/s
    np.testing.assert_allclose(frames.gcrs_to_itrs(g, e, eop), x_itrf, rtol=0, atol=1e-11)
    m = frames.gcrs_to_itrs_matrix(e, eop)
    np.testing.assert_allclose(m @ m.T, np.eye(3), atol=1e-15)
    np.testing.assert_allclose(frames.itrs_to_gcrs(x_itrf[:3], e, eop), g[:3], atol=1e-11)


def test_eme2000_bias_and_iau_rotation():
    b = frames.gcrs_to_eme2000_matrix()
    assert b[0, 1] == pytest.approx(-0.7078368960971557145e-7, abs=1e-14)  # t_erfa_c t_bp06
    v = np.array([7000.0, -100.0, 300.0, 1.0, 7.0, 0.5])
    np.testing.assert_allclose(frames.eme2000_to_gcrs(frames.gcrs_to_eme2000(v)), v, atol=1e-11)
    fin = frames.load_eop(FINALS)
    e0 = Epoch.parse("2016-12-10T00:00:00")
    rot = frames.IauEarthRotation(e0, fin, 0.0, 86400.0)
    r, w = rot.rotation(40000.0)
    full = frames.earth_orientation(e0 + 40000.0, fin)
    angle = math.acos(min(1.0, (np.trace(r.T @ full.gcrs_to_itrs) - 1.0) / 2.0))
    assert angle < 1e-7  # acos of a trace: ~sqrt(eps) resolution; the C++ test measures 2.9e-12 rad
    assert np.linalg.norm(w) == pytest.approx(full.omega, rel=1e-12)


def _enu_numpy(lat_deg, lon_deg):
    """An independent east/north/up basis from geodetic latitude and longitude."""
    p, lam = math.radians(lat_deg), math.radians(lon_deg)
    east = np.array([-math.sin(lam), math.cos(lam), 0.0])
    up = np.array([math.cos(p) * math.cos(lam), math.cos(p) * math.sin(lam), math.sin(p)])
    return east, np.cross(up, east), up


def test_ground_station_against_numpy():
    s = frames.GroundStation(48.0, 11.3, 0.6, elevation_mask_deg=5.0, name="OBP")
    # Geodetic -> ITRF, WGS-84 (a = 6378.137 km, f = 1/298.257223563), re-derived here.
    a, f = 6378.137, 1 / 298.257223563
    e2 = f * (2 - f)
    p, lam = math.radians(48.0), math.radians(11.3)
    n = a / math.sqrt(1 - e2 * math.sin(p) ** 2)
    r = np.array([(n + 0.6) * math.cos(p) * math.cos(lam), (n + 0.6) * math.cos(p) * math.sin(lam),
                  (n * (1 - e2) + 0.6) * math.sin(p)])
    np.testing.assert_allclose(s.position_itrf, r, rtol=0, atol=1e-9)  # km; ulps of 6400 km
    sat = np.array([4500.0, 1500.0, 5300.0, -3.0, 6.0, 2.5])
    east, north, up = _enu_numpy(48.0, 11.3)
    rho = sat[:3] - r
    el = math.asin(rho @ up / np.linalg.norm(rho))
    az = math.atan2(rho @ east, rho @ north) % (2 * math.pi)
    look = s.look_itrf(sat)
    assert look.elevation == pytest.approx(el, abs=1e-12) and look.azimuth == pytest.approx(az, abs=1e-12)
    assert look.range_rate == pytest.approx(rho @ sat[3:] / np.linalg.norm(rho), abs=1e-12)
    assert s.visible(look.elevation) == (look.elevation >= math.radians(5.0))
    fin = frames.load_eop(FINALS)
    e = Epoch.parse("2016-12-20T10:00:00")
    x = s.state_gcrf(e, fin)
    assert np.linalg.norm(x[:3]) == pytest.approx(np.linalg.norm(r), abs=1e-9)
    assert np.linalg.norm(x[3:]) == pytest.approx(7.292115146706979e-5 * math.hypot(r[0], r[1]), rel=1e-3)


def test_ground_station_bad_input():
    msg = (r"height_km: -0.700000 km is below the WGS-84 ellipsoid by more than the deepest real station "
           r"\(limit -0.5 km; the Dead Sea shore is -0.43 km\)")
    with pytest.raises(ValueError, match=msg):
        frames.GroundStation(31.5, 35.5, -0.7)
    frames.GroundStation(31.5, 35.5, -0.43, name="Dead Sea shore")
    with pytest.raises(ValueError, match="latitude_deg: must be in"):
        frames.GroundStation(91.0, 0.0, 0.0)
    with pytest.raises(ValueError, match=r"satellite_itrf: must have shape \(6,\)"):
        frames.GroundStation(0.0, 0.0, 0.0).look_itrf(np.zeros(3))
    with pytest.raises(ValueError, match=r"x: must have shape \(3,\) \(position, km\) or \(6,\)"):
        frames.gcrs_to_eme2000(np.zeros(4))

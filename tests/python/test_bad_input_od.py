"""Bad input to the orbit-determination API (the numeric entry points; file readers and the CLI have
their own tables). Rows: (callable, kwargs, exception type, message fragment naming the argument)."""

from __future__ import annotations

import numpy as np
import pytest
from _bad_input import ARGNAMES, case_ids, check_bad_input
from satgnc import od
from satgnc.od.tdm import parse_epoch

X = np.array([7000.0, 0.0, 0.0, 0.0, 7.5, 0.0])
STATION = np.array([6378.0, 0.0, 0.0, 0.0, 0.465, 0.0])


def _predict(**kw):
    args = dict(kind="range", x=X, station_state=STATION)
    args.update(kw)
    return od.predict(**args)


def _set(**kw):
    s = od.OdSettings()
    for k, v in kw.items():
        setattr(s, k, v)


def _box(**kw):
    args = dict(center=X, half_width=np.ones(6), n=4)
    args.update(kw)
    return od.box_guesses(**args)


STATION_OBJ = od.station_inertial(STATION[:3])


def _roots(**kw):
    st = od.station_inertial([6378.0, 0.0, 0.0])
    obs = od.simulate(X, st, np.arange(0.0, 301.0, 30.0), seed=None)
    return od.root_search(od.solver(obs, st), **kw)


def _six(**kw):
    args = dict(t=np.arange(6.0), rho=np.full(6, 1000.0), rhodot=np.zeros(6))
    args.update(kw)
    return od.six_point_conditions(**args)


def _obs(**kw):
    args = dict(t=np.arange(6.0), type="range", value=np.full(6, 1000.0), sigma=1e-3, station=0)
    args.update(kw)
    return od.Observations(**args)


def _solver_solve(**kw):
    st = od.station_inertial([6378.0, 0.0, 0.0])
    m = [od._c.Measurement(float(t), od.MeasurementType.range, 700.0, 1e-3, 0) for t in range(0, 60, 10)]
    s = od.OdSolver.from_measurements([st], m, od.make_propagator("kepler"), od.OdSettings())
    return s.solve(**kw)


CASES = [
    # fuzz pass
    (od.six_point_conditions, dict(t=[0.0, 1, 2, 3, 4, 5], rho=[1e3] * 6, rhodot=[0.1] * 6, mode=3),
     TypeError, "mode: must be 'doppler', 'range' or a list"),  # "'int' object is not iterable"
    (od.six_point_conditions, dict(t=[0.0, 1, 2, 3, 4, 5], rho=[1e3] * 6, rhodot=[0.1] * 6, mode=None),
     TypeError, "mode:"),
    (parse_epoch, dict(text="no-such-epoch"), ValueError, "text: bad epoch"),  # named nothing
    (_predict, dict(x=[1e300, 0, 0, 0, 7.5, 0]), ValueError, "x: every component must be below 1e100"),  # NaN
    (lambda **kw: od.implied_rotation_rate(**kw), dict(station_state=[1e300, 1, 0, 0, 0.4, 0]), ValueError,
     "station_state:"),  # NaN
    (lambda **kw: od.simulate(X, [od.station_inertial(STATION[:3])], np.linspace(0.0, 300.0, 7), seed=1,
                              **kw),
     dict(sigma_range=1e300), ValueError, "sigma_range, bias_range: the simulated noise"),  # named "value"
    # time and frame inputs out of their physical range
    (lambda **kw: od.gmst("2020-01-01T00:00:00", **kw), dict(ut1_minus_utc=5), ValueError,
     "ut1_minus_utc: |UT1 - UTC| must be < 0.9 s"),
    (lambda **kw: od.gmst("2020-01-01T00:00:00", **kw), dict(ut1_minus_utc=-0.95), ValueError,
     "ut1_minus_utc:"),
    (lambda **kw: od.station_geodetic(0.0, 0.0, 0.0, "2020-01-01T00:00:00", **kw), dict(ut1_minus_utc=1.0),
     ValueError, "ut1_minus_utc:"),
    (od.gmst, dict(epoch="1850-01-01T00:00:00"), ValueError, "epoch: 1850-01-01T00:00:00 is out of range"),
    (od.gmst, dict(epoch="2200-01-01T00:00:00"), ValueError, "epoch:"),  # named "year"
    (od.julian_date, dict(epoch=2.4e6), ValueError, "epoch: a Julian date must be finite and in"),
    (od.julian_date, dict(epoch=np.int64(2_400_000)), ValueError, "epoch:"),
    (od.julian_date, dict(epoch=np.bool_(True)), TypeError, "epoch:"),
    (lambda **kw: od._c.od_julian_date(2021, 2, **kw), dict(day=29, hour=0, minute=0, second=0.0), ValueError,
     "day: must be in 1..28 for month 2 of 2021"),  # read as 2021-03-01
    (lambda **kw: od._c.od_gmst_from_utc(2459000.5, **kw), dict(ut1_minus_utc_s=5.0), ValueError,
     "ut1_minus_utc_s:"),
    # make_propagator named "propagator" for its own argument "kind"; solve/simulate name "propagator"
    (od.make_propagator, dict(kind="rk4"), ValueError, "kind: unknown propagator 'rk4'"),
    (od.make_propagator, dict(kind=3), TypeError, "kind: must be 'kepler', 'cvodes' or a propagator"),
    # complex / boolean / object / string arrays
    (_predict, dict(x=X.astype(complex)), TypeError, "x:"),
    (_predict, dict(x=np.ones(6, dtype=bool)), TypeError, "x:"),
    (_predict, dict(station_state=np.array(list(STATION[:5]) + ["0"], dtype=object)), TypeError,
     "station_state:"),
    (_predict, dict(x="7000 0 0 0 7.5 0"), TypeError, "x:"),
    (lambda **kw: od.station_inertial(**kw), dict(r0=np.array([1j, 0, 0])), TypeError, "r0:"),
    (lambda **kw: od.implied_rotation_rate(**kw), dict(station_state=np.ones(6, dtype=bool)), TypeError,
     "station_state:"),
    (_box, dict(center=X + 0j), TypeError, "center:"),
    (_box, dict(half_width=np.ones(6, dtype=bool)), TypeError, "half_width:"),
    (_solver_solve, dict(x0=X.astype(complex)), TypeError, "x0:"),
    (_solver_solve, dict(x0=np.ones(6, dtype=bool)), TypeError, "x0:"),
    # NaN / Inf, shapes
    (_predict, dict(x=[np.nan, 0, 0, 0, 7.5, 0]), ValueError, "x:"),
    (_predict, dict(x=X[:5]), ValueError, "x:"),
    (lambda **kw: od.geodetic_to_ecef(**kw), dict(lat_deg=np.nan, lon_deg=0.0, height_km=0.0), ValueError,
     "lat_deg:"),
    (lambda **kw: od.gmst("2020-01-01T00:00:00", **kw), dict(ut1_minus_utc=np.inf), ValueError,
     "ut1_minus_utc:"),
    # wrong types for numbers / ints, out of range, huge sizes
    (lambda **kw: od.geodetic_to_ecef(**kw), dict(lat_deg="45", lon_deg=0.0, height_km=0.0), TypeError,
     "lat_deg:"),
    (lambda **kw: od.geodetic_to_ecef(**kw), dict(lat_deg=True, lon_deg=0.0, height_km=0.0), TypeError,
     "lat_deg:"),
    (lambda **kw: od.geodetic_to_ecef(**kw), dict(lat_deg=95.0, lon_deg=0.0, height_km=0.0), ValueError,
     "lat_deg:"),
    (_box, dict(seed=-1), ValueError, "seed:"),
    (_box, dict(seed="x"), TypeError, "seed:"),
    (_box, dict(seed=2**70), ValueError, "seed:"),
    (_box, dict(n=10**12), ValueError, "n:"),
    (_set, dict(max_iterations="x"), TypeError, "max_iterations:"),
    (_set, dict(max_iterations=1.5), TypeError, "max_iterations:"),
    (_set, dict(max_iterations=2**40), ValueError, "max_iterations:"),
    (_set, dict(max_iterations=0), ValueError, "max_iterations:"),
    (_set, dict(step_tol=np.nan), ValueError, "step_tol:"),
    (_set, dict(mu="earth"), TypeError, "mu:"),
    (_set, dict(fit_sigma=1j), TypeError, "fit_sigma:"),
    (_set, dict(method="newton_raphson"), ValueError, "method:"),
    (_set, dict(method=2), TypeError, "method:"),
    (_set, dict(valley_corrections="3"), TypeError, "valley_corrections:"),
    (_set, dict(valley_corrections=2.5), TypeError, "valley_corrections:"),
    (_set, dict(valley_corrections=-1), ValueError, "valley_corrections:"),
    (_set, dict(valley_corrections=101), ValueError, "valley_corrections:"),
    (_set, dict(extrapolate="no"), TypeError, "extrapolate:"),
    (_set, dict(extrapolate=np.array([1, 0])), TypeError, "extrapolate:"),
    # found by the QA probe (issue 11 verification): each was accepted silently or unclear before
    (_roots, dict(guesses=np.array([X]) + 0j), TypeError, "guesses:"),  # truncated to real
    (_roots, dict(guesses=np.ones((1, 6), dtype=bool)), TypeError, "guesses:"),  # read as 1 km
    (_roots, dict(guesses="x"), TypeError, "guesses:"),  # "could not convert string to float"
    (_six, dict(t=[np.nan] * 6), ValueError, "t:"),  # accepted
    (_six, dict(rho=-np.ones(6)), ValueError, "rho:"),  # accepted
    (_six, dict(rhodot=np.full(6, np.inf)), ValueError, "rhodot:"),  # accepted
    (_six, dict(station=-1), ValueError, "station:"),  # accepted
    (_six, dict(station="a"), TypeError, "station:"),  # "invalid literal for int()"
    (_obs, dict(value=np.full(6, -1000.0)), ValueError, "value:"),  # negative range accepted
    (_obs, dict(station=-1), ValueError, "station:"),  # accepted until solve
    (_obs, dict(sigma=1e-3 + 0j), TypeError, "sigma:"),  # truncated to real
    (_box, dict(n=True), ValueError, "n:"),  # read as n = 1
    (lambda **kw: od.simulate(X, **kw), dict(stations=None, times=[0.0, 10.0]), TypeError, "stations:"),
    # blamed x0 ("propagation failed"), before issue 11 the force model
    (lambda **kw: od.simulate(X, STATION_OBJ, **kw), dict(times=[0.0, 1e300]), ValueError, "times:"),
    (lambda **kw: parse_epoch(**kw), dict(text=3), TypeError, "text:"),  # AttributeError on .strip
]


@pytest.mark.parametrize(ARGNAMES, CASES, ids=case_ids(CASES))
def test_bad_input_names_the_argument(fn, kwargs, exc, fragment):
    check_bad_input(fn, kwargs, exc, fragment)


def test_bad_alloc_names_the_size_argument():
    # std::bad_alloc reaches Python as MemoryError; the hardened wrapper names the largest size.
    from satgnc import _validate

    def engine(center, half_width, n, seed):
        raise MemoryError

    engine.__doc__ = ("od_box_guesses(center: numpy.ndarray, half_width: numpy.ndarray, "
                      "n: typing.SupportsInt, seed: typing.SupportsInt) -> numpy.ndarray")

    wrapped = _validate._wrap_callable(engine, "od_box_guesses")
    with pytest.raises(ValueError, match=r"^n: 3000000000 is too large: od_box_guesses could not allocate"):
        wrapped(np.ones(6), np.ones(6), 3_000_000_000, 7)

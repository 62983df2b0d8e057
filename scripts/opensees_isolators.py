"""OpenSees as a peer of floorslide's solvers for buildings on nonlinear isolation.

The 2-storey superstructure of tests/building/test_nonlinear_approx.py (``ShearBuilding.
from_period(stories=2, period=0.4, damping=0.03)``, base mass ratio 1) is built in OpenSees
(2-D, three DOF per node): a fixed ground node, the base mat on it through the isolator
element, the floors as lumped masses, each storey a ``zeroLength`` element with an ``Elastic``
material (stiffness and viscous ``eta``). The superstructure's damping matrix is reproduced
exactly by dashpots (``Elastic`` with ``eta``) between the base and each floor and between the
floors (a symmetric matrix on the drifts with non-negative row sums and non-positive
off-diagonal terms is such a network); no Rayleigh damping. Isolators:

- ``elastomericBearingPlasticity`` (bilinear): ``kInit = k1``, ``qd = Q``, ``alpha1 = k2/k1``,
  ``alpha2 = 0`` (the script prints the force envelope ``max|f − k2·u|/Q`` it gets: 1);
- ``singleFPBearing`` with ``frictionModel Coulomb`` (pendulum): ``Reff = R`` and
  ``kInit = W/R + mu·W/y`` for a friction elastic displacement ``y`` (floorslide's
  ``friction_yield``, 0.25 mm by default); the normal force comes from a static gravity step
  (the building's weight on the mat's vertical DOF, an elastic axial material), and the
  element adds to it the second-order term ``f·u0/R`` that floorslide's models do not have.

El Centro (ELC-180) is applied with ``UniformExcitation`` of a ``Path`` series at its dt,
integrated by ``Newmark 0.5 0.25`` with ``Newton`` and ``NormDispIncr 1e-12`` on dt/1, dt/4,
dt/16. Peak isolator displacement, residual, PFA and wall time are printed beside floorslide's
exact solver and its Newmark (:func:`floorslide.building.nonlinear_approx.
newmark_isolator_response`, which should agree with OpenSees to the second-order normal-force
term).

openseespy is not a dependency of floorslide: install it in a separate environment and give
its interpreter::

    python3 -m venv /tmp/ops-venv && /tmp/ops-venv/bin/pip install openseespy numpy
    PYTHONPATH=. .venv/bin/python scripts/opensees_isolators.py \\
        --opensees-python /tmp/ops-venv/bin/python

(Where the system has no ``libblas.so.3`` — "Failed to import openseespy on Linux" — point
``LD_LIBRARY_PATH`` at the copy the wheel bundles,
``/tmp/ops-venv/lib/python3.11/site-packages/openseespylinux/lib``.)

What it shows (15 s): OpenSees and floorslide's Newmark agree to 7e-4, 2e-4, 4e-5 of the peak
isolator displacement (bilinear) at dt/1, /4, /16 — the difference of their starts: OpenSees
begins the transient with zero acceleration, floorslide from equilibrium (``−a_g(0)``
relative); with ``--zero-start`` (a record that starts at 0) they agree to 1e-11. The pendulum
differs by 2e-3 either way (the normal force's ``f·u0/R``). Both are 19 % from the exact
pendulum in ``u0``: the elastic friction rings after each stop (see
:mod:`floorslide.building.nonlinear_approx`).

The OpenSees side runs in that interpreter (``--worker``, numpy and openseespy only). The
openseespylinux 3.7.1 wheel ships ``libblas.so.3`` without a run path to it; the worker then
loads it before importing openseespy.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
G = 9.80665


# --------------------------------------------------------------------------------------------
# worker: OpenSees only (numpy and openseespy)
# --------------------------------------------------------------------------------------------


def _import_opensees():
    try:
        import openseespy.opensees as ops
    except (ImportError, RuntimeError):
        import ctypes
        import importlib.util

        spec = importlib.util.find_spec("openseespylinux")
        if spec is None or not spec.submodule_search_locations:
            raise
        lib = Path(next(iter(spec.submodule_search_locations))) / "lib" / "libblas.so.3"
        ctypes.CDLL(str(lib), mode=ctypes.RTLD_GLOBAL)
        import openseespy.opensees as ops
    return ops


def _storeys(Ks: np.ndarray, Cs: np.ndarray):
    """Springs and dashpots ``(i, j, k, c)`` (node 0 = the base) whose assembly on the drifts is
    ``Ks``, ``Cs``."""
    n = Ks.shape[0]
    out = []
    for i in range(n):
        k0 = Ks[i].sum()
        c0 = Cs[i].sum()
        if k0 < -1e-12 * abs(Ks).max() or c0 < -1e-12 * abs(Cs).max():
            raise ValueError("the superstructure matrices are not a spring/dashpot network")
        if k0 != 0 or c0 != 0:
            out.append((0, i + 1, max(k0, 0.0), max(c0, 0.0)))
        for j in range(i + 1, n):
            if Ks[i, j] > 0 or Cs[i, j] > 0:
                raise ValueError("the superstructure matrices are not a spring/dashpot network")
            if Ks[i, j] != 0 or Cs[i, j] != 0:
                out.append((i + 1, j + 1, -Ks[i, j], -Cs[i, j]))
    return out


def run_opensees(spec: dict) -> dict:
    """One analysis in OpenSees; `spec` as written by :func:`main`."""
    ops = _import_opensees()
    m = np.asarray(spec["mass"])  # mat, then floors
    Ks = np.asarray(spec["Ks"])
    Cs = np.asarray(spec["Cs"])
    acc = np.asarray(spec["acc"])
    dt = spec["dt"]
    k = spec["substeps"]
    c = spec["constants"]
    W = c["W"]
    n = m.size
    ops.wipe()
    ops.model("basic", "-ndm", 2, "-ndf", 3)
    ops.node(100, 0.0, 0.0)
    ops.fix(100, 1, 1, 1)
    for i in range(n):
        ops.node(i + 1, 0.0, 0.0)
        ops.mass(i + 1, float(m[i]), 0.0, 0.0)
    ops.fix(1, 0, 1 if spec["kind"] == "bilinear" else 0, 1)
    for i in range(2, n + 1):
        ops.fix(i, 0, 1, 1)
    tag = 10
    for i, j, ks, cs in _storeys(Ks, Cs):
        ops.uniaxialMaterial("Elastic", tag, float(ks), float(cs))
        ops.element("zeroLength", tag, i + 1, j + 1, "-mat", tag, "-dir", 1)
        tag += 1
    axial = 1e6 * W  # N/m: stiff, elastic
    ops.uniaxialMaterial("Elastic", 1, axial)
    ops.uniaxialMaterial("Elastic", 2, 0.0)
    if spec["kind"] == "bilinear":
        k1, k2 = c["k1"], c["k2"]
        alpha = k2 / k1
        # the strength argument is the characteristic strength Q in openseespy 3.7.1 (the
        # force envelope max|f − k2·u| printed below is Q)
        ops.element(
            "elastomericBearingPlasticity", 1, 100, 1, k1, c["Q"], alpha, 0.0, 2.0,
            "-P", 1, "-Mz", 2, "-orient", 0.0, 1.0, 0.0, -1.0, 0.0, 0.0,
        )  # fmt: skip
    else:
        y = spec["friction_yield"]
        R = c["R"]
        ops.frictionModel("Coulomb", 1, c["mu"])
        k_init = W / R + c["mu"] * W / y
        ops.element(
            "singleFPBearing", 1, 100, 1, 1, R, k_init,
            "-P", 1, "-Mz", 2, "-orient", 0.0, 1.0, 0.0, -1.0, 0.0, 0.0,
        )  # fmt: skip
        # gravity: the building's weight on the mat
        ops.timeSeries("Linear", 1)
        ops.pattern("Plain", 1, 1)
        ops.load(1, 0.0, -W, 0.0)
        ops.system("BandGeneral")
        ops.numberer("Plain")
        ops.constraints("Plain")
        ops.test("NormDispIncr", 1e-12, 20)
        ops.algorithm("Newton")
        ops.integrator("LoadControl", 0.1)
        ops.analysis("Static")
        if ops.analyze(10) != 0:
            raise RuntimeError("gravity analysis failed")
        ops.loadConst("-time", 0.0)
        ops.wipeAnalysis()
    # one more sample: the clock's rounding must not carry the last step past the series' end,
    # where a Path series is 0
    ops.timeSeries("Path", 2, "-dt", dt, "-values", *acc.tolist(), float(acc[-1]))
    ops.pattern("UniformExcitation", 2, 1, "-accel", 2)
    ops.system("BandGeneral")
    ops.numberer("Plain")
    ops.constraints("Plain")
    ops.test("NormDispIncr", 1e-12, 50)
    ops.algorithm("Newton")
    ops.integrator("Newmark", 0.5, 0.25)
    ops.analysis("Transient")
    h = dt / k
    npts = acc.size
    u0 = np.zeros(npts)
    force = np.zeros(npts)
    a_abs = np.zeros((n, npts))
    peak = np.zeros(n + 2)
    failed = 0
    t0 = time.perf_counter()
    for s in range(npts - 1):
        for _ in range(k):
            if ops.analyze(1, h) != 0:
                failed += 1
            t = ops.getTime()
            ag = np.interp(t, [s * dt, (s + 1) * dt], [acc[s], acc[s + 1]])
            ai = np.array([ops.nodeAccel(i + 1, 1) for i in range(n)]) + ag
            f = ops.eleResponse(1, "force")[3]  # on the mat, global X
            x = ops.nodeDisp(1, 1)
            peak[:n] = np.maximum(peak[:n], np.abs(ai))
            peak[n] = max(peak[n], abs(f))
            peak[n + 1] = max(peak[n + 1], abs(x))
        a_abs[:, s + 1] = ai
        force[s + 1] = f
        u0[s + 1] = x
    elapsed = time.perf_counter() - t0
    ops.wipe()
    return {
        "u0": u0.tolist(),
        "force": force.tolist(),
        "a_abs": a_abs.tolist(),
        "peak": peak.tolist(),
        "elapsed": elapsed,
        "failed": failed,
    }


# --------------------------------------------------------------------------------------------
# driver: floorslide beside OpenSees
# --------------------------------------------------------------------------------------------


def _row(name, method, ex, pk, res, pfa, u, a, t, extra=""):
    """One line of the table: peaks, residual, errors against the exact response `ex`."""
    su = np.abs(ex.isolator_displacement).max()
    sa = np.abs(ex.floor_acceleration).max()
    print(
        f"{name:9s} {method:18s} {pk:12.6f} {res:11.6f} "
        f"{' '.join(f'{v:6.3f}' for v in pfa):>22s} "
        f"{np.abs(u - ex.isolator_displacement).max() / su:13.2e} "
        f"{np.abs(a - ex.floor_acceleration).max() / sa:12.2e} {t:9.4f}{extra}"
    )


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--opensees-python", default=sys.executable, help="interpreter with openseespy")
    p.add_argument("--seconds", type=float, default=15.0, help="length of El Centro used, s")
    p.add_argument("--substeps", type=int, nargs="+", default=[1, 4, 16])
    p.add_argument(
        "--zero-start",
        action="store_true",
        help="prepend a zero sample to the record (OpenSees starts from zero acceleration)",
    )
    p.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    args = p.parse_args(argv)
    if args.worker:
        json.dump(run_opensees(json.load(sys.stdin)), sys.stdout)
        return 0

    import floorslide as fs
    from floorslide.building.isolators import BilinearIsolator, FrictionPendulum
    from floorslide.building.nonlinear import NonlinearIsolatedBuilding, isolator_response
    from floorslide.building.nonlinear_approx import (
        FRICTION_YIELD_DISP,
        newmark_isolator_response,
    )

    dt = 0.01
    npts = round(args.seconds / dt) + 1
    acc = np.loadtxt(ROOT / "data/records/slammer/ImperialValley_1940_ELC-180.txt")[:npts] * G
    if args.zero_start:
        acc = np.concatenate([[0.0], acc])
    sup = fs.ShearBuilding.from_period(stories=2, period=0.4, damping=0.03)
    cases = {
        "bilinear": BilinearIsolator(q_ratio=0.06, period=2.5, yield_disp=0.02),
        "pendulum": FrictionPendulum(mu=0.06, period=3.0),
    }
    print(f"El Centro ELC-180, first {args.seconds:g} s, dt = {dt}; 2-storey superstructure")
    head = (
        f"{'case':9s} {'method':18s} {'peak u0 [m]':>12s} {'resid. [m]':>11s} "
        f"{'PFA 0/1/2 [m/s2]':>22s} {'max|u0-ex|/pk':>13s} {'max|a-ex|/pk':>12s} "
        f"{'time [s]':>9s}"
    )
    for name, iso in cases.items():
        b = NonlinearIsolatedBuilding(sup, 1.0, iso)
        isolator_response(b, acc[:20], dt)
        t0 = time.perf_counter()
        ex = isolator_response(b, acc, dt)
        t_ex = time.perf_counter() - t0
        su = np.abs(ex.isolator_displacement).max()
        print()
        print(head)

        _row(
            name, "floorslide exact", ex, ex.peak_displacement, ex.residual_displacement, ex.pfa,
            ex.isolator_displacement, ex.floor_acceleration, t_ex,
        )  # fmt: skip
        spec = {
            "kind": "bilinear" if name == "bilinear" else "pendulum",
            "mass": b.mass.tolist(),
            "Ks": sup.stiffness_matrix.tolist(),
            "Cs": sup.damping_matrix.tolist(),
            "constants": {key: float(v) for key, v in b.constants.items()},
            "friction_yield": FRICTION_YIELD_DISP,
            "acc": acc.tolist(),
            "dt": dt,
        }
        for k in args.substeps:
            newmark_isolator_response(b, acc[:20], dt, substeps=k)
            nm = newmark_isolator_response(b, acc, dt, substeps=k)
            _row(
                name, f"fs Newmark dt/{k}", ex, nm.peak_displacement,
                nm.residual_displacement, nm.pfa, nm.isolator_displacement,
                nm.floor_acceleration, nm.elapsed,
            )  # fmt: skip
            spec["substeps"] = k
            proc = subprocess.run(
                [args.opensees_python, __file__, "--worker"],
                input=json.dumps(spec),
                capture_output=True,
                text=True,
                check=False,
            )
            if proc.returncode != 0:
                print(f"OpenSees failed:\n{proc.stderr[-2000:]}")
                return 1
            out = json.loads(proc.stdout)
            u = np.asarray(out["u0"])
            a = np.asarray(out["a_abs"])
            f = np.asarray(out["force"])
            pk = out["peak"]
            n = b.n_dof
            d_nm = np.abs(u - nm.isolator_displacement).max() / su
            extra = f"   vs fs Newmark: u0 {d_nm:.1e}"
            if out["failed"]:
                extra += f", {out['failed']} steps failed"
            _row(
                name, f"OpenSees dt/{k}", ex, pk[n + 1], u[-1], pk[:n], u, a, out["elapsed"], extra
            )
            if name == "bilinear":
                c = b.constants
                env = np.abs(f - c["k2"] * u).max() / c["Q"]
                print(f"{'':9s} {'':18s} OpenSees force envelope max|f − k2·u|/Q = {env:.6f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""OpenSees as a peer of floorslide's solvers for buildings on nonlinear isolation.

Default mode, El Centro in one direction: the 2-storey superstructure of
tests/building/test_nonlinear_approx.py (``ShearBuilding.from_period(stories=2, period=0.4,
damping=0.03)``, base mass ratio 1) is built in OpenSees (2-D, three DOF per node): a fixed
ground node, the base mat on it through the isolator element, the floors as lumped masses,
each storey a ``zeroLength`` element with an ``Elastic`` material (stiffness and viscous
``eta``). The superstructure's damping matrix is reproduced exactly by dashpots (``Elastic``
with ``eta``) between the base and each floor and between the floors (a symmetric matrix on
the drifts with non-negative row sums and non-positive off-diagonal terms is such a network);
no Rayleigh damping. Isolators:

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

Bidirectional mode (``--plane``): the same superstructure in 3-D (``-ndm 3 -ndf 6``, rotations
fixed) under two horizontal components, each storey's springs and dashpots along X and Y
(``zeroLength``, ``-dir 1 2``), one ``UniformExcitation`` per component (h1 along X, h2 along
Y). The bearings are the 3-D elements, both with a circular yield surface:
``elastomericBearingPlasticity`` (as above) and ``singleFPBearing`` (Coulomb, ``kInit = W/R +
mu·W/y``, the gravity step as above); a control ``flatSliderBearing`` (``kInit − W/R``) beside a
linear spring ``W/R`` is floorslide's pendulum model in OpenSees (``--no-control`` skips it).
They are set beside floorslide's exact coupled solver (pendulum,
:func:`floorslide.building.plane_isolation.plane_isolator_response`) and its 2-D Newmark
(:func:`floorslide.building.plane_isolation_approx.newmark_plane_isolator_response`) on
Sylmar (RSN1084, 052 + 142, first 3000 samples at 0.005 s) at scales 1 and 0.3, printing
markdown tables: peak ``|u_b|`` and direction, residual vector, roof PFA ``max |a|``.

What it shows (24 s): lead-rubber, OpenSees = floorslide's Newmark to 4.6e-5, 1.2e-5, 2.9e-6
of the peak at dt/1, /4, /16 (the start, as in 1-D; with ``--zero-start`` 5e-12, 6e-11,
2e-9), OpenSees' force envelope ``max |f − k2·u|/Q`` 1. Pendulum at scale 0.3 (``u_b`` 0.096 m
= 0.043 R): 2.2e-3 as in 1-D, and the control matches floorslide's Newmark to 1e-5 .. 4e-7
(5e-13 .. 5e-10 from a zero start), so the difference is all the element's normal force ``W +
q·u/R`` (with radii ``sqrt(R² − u_other²)``). At scale 1 the bearing reaches 0.98 m = 0.44 R
(the exact solver notes it is beyond its small-angle range): that normal force reaches 1.28 W,
so the peak is only 0.7 % larger (0.988 against 0.982 m at dt/16, 1° apart) but the roof PFA
is 31 % higher (6.51 against 4.97 m/s²) and the orbit drifts 0.39 of the peak away (residual
(0.107, 0.039) against (0.087, 0.044) m) — a large-displacement model that floorslide's does
not claim to be.
floorslide's Newmark is 8e-3 .. 1e-2 (scale 1) and 6e-2 (scale 0.3, peak +6 %) from the exact
pendulum at every dt/k: the elastic friction element, not the step. Wall time per run: exact
0.03 s, floorslide's Newmark 0.3 .. 7 ms, OpenSees 0.15 .. 2.7 s.

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
PAIRS = ROOT / "data/records/pairs"
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


def run_opensees_plane(spec: dict) -> dict:
    """One analysis of the bidirectional model in OpenSees (3-D, six DOF per node); `spec` as
    written by :func:`main_plane`.

    ``spec["kind"]``: ``"bilinear"`` (``elastomericBearingPlasticity``), ``"pendulum"``
    (``singleFPBearing``) or ``"flat"`` (the control: ``flatSliderBearing`` beside an elastic
    spring ``W/R``, floorslide's pendulum without the second-order term).

    Returns the bearing's displacement vector and every floor's absolute acceleration vector at
    the samples, the bearing's force vector on the mat (the friction element's alone for
    ``"flat"``), the pendulum's normal force, the largest ``|u_b|`` over the sub-steps and its
    direction, the wall time and the steps that did not converge.
    """
    ops = _import_opensees()
    m = np.asarray(spec["mass"])  # mat, then floors
    Ks = np.asarray(spec["Ks"])
    Cs = np.asarray(spec["Cs"])
    acc = np.asarray(spec["acc"])  # (2, npts): h1 along X, h2 along Y
    dt = spec["dt"]
    k = spec["substeps"]
    c = spec["constants"]
    W = c["W"]
    n = m.size
    bilinear = spec["kind"] == "bilinear"
    ops.wipe()
    ops.model("basic", "-ndm", 3, "-ndf", 6)
    ops.node(100, 0.0, 0.0, 0.0)
    ops.fix(100, 1, 1, 1, 1, 1, 1)
    for i in range(n):
        ops.node(i + 1, 0.0, 0.0, 0.0)
        ops.mass(i + 1, float(m[i]), float(m[i]), 0.0, 0.0, 0.0, 0.0)
    # the mat: free in X, Y (and Z on the pendulum, carrying the weight); the floors: X, Y
    ops.fix(1, 0, 0, 1 if bilinear else 0, 1, 1, 1)
    for i in range(2, n + 1):
        ops.fix(i, 0, 0, 1, 1, 1, 1)
    tag = 10
    for i, j, ks, cs in _storeys(Ks, Cs):
        ops.uniaxialMaterial("Elastic", tag, float(ks), float(cs))
        ops.element("zeroLength", tag, i + 1, j + 1, "-mat", tag, tag, "-dir", 1, 2)
        tag += 1
    if c.get("c", 0.0) > 0:  # the layer's viscous damping, if any
        ops.uniaxialMaterial("Elastic", tag, 0.0, float(c["c"]))
        ops.element("zeroLength", tag, 100, 1, "-mat", tag, tag, "-dir", 1, 2)
    axial = 1e6 * W  # N/m: stiff, elastic
    ops.uniaxialMaterial("Elastic", 1, axial)
    ops.uniaxialMaterial("Elastic", 2, 0.0)
    # local x along global Z (the bearing's axis), local y = X, local z = Y
    orient = ("-orient", 0.0, 0.0, 1.0, 1.0, 0.0, 0.0)
    mats = ("-P", 1, "-T", 2, "-My", 2, "-Mz", 2)
    if bilinear:
        k1, k2 = c["k1"], c["k2"]
        ops.element(
            "elastomericBearingPlasticity", 1, 100, 1, k1, c["Q"], k2 / k1, 0.0, 2.0,
            *mats, *orient,
        )  # fmt: skip
    else:
        y = spec["friction_yield"]
        R = c["R"]
        ops.frictionModel("Coulomb", 1, c["mu"])
        k_init = W / R + c["mu"] * W / y
        if spec["kind"] == "flat":
            # control: floorslide's model (a friction element on the constant normal force W
            # beside a linear spring W/R), which singleFPBearing is up to its q·u/R term
            ops.element("flatSliderBearing", 1, 100, 1, 1, k_init - W / R, *mats, *orient)
            ops.uniaxialMaterial("Elastic", 3, W / R)
            ops.element("zeroLength", 2, 100, 1, "-mat", 3, 3, "-dir", 1, 2)
        else:
            ops.element("singleFPBearing", 1, 100, 1, 1, R, k_init, *mats, *orient)
        ops.timeSeries("Linear", 1)
        ops.pattern("Plain", 1, 1)
        ops.load(1, 0.0, 0.0, -W, 0.0, 0.0, 0.0)
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
    for d in range(2):  # one more sample each, as in run_opensees
        ops.timeSeries("Path", 2 + d, "-dt", dt, "-values", *acc[d].tolist(), float(acc[d, -1]))
        ops.pattern("UniformExcitation", 2 + d, d + 1, "-accel", 2 + d)
    ops.system("BandGeneral")
    ops.numberer("Plain")
    ops.constraints("Plain")
    ops.test("NormDispIncr", 1e-12, 50)
    ops.algorithm("Newton")
    ops.integrator("Newmark", 0.5, 0.25)
    ops.analysis("Transient")
    h = dt / k
    npts = acc.shape[1]
    u = np.zeros((npts, 2))
    force = np.zeros((npts, 2))
    normal = np.zeros(npts)
    a_abs = np.zeros((npts, n, 2))  # at rest at t = 0, the ground not yet applied (OpenSees)
    peak = 0.0
    peak_dir = 0.0
    failed = 0
    t0 = time.perf_counter()
    for s in range(npts - 1):
        for _ in range(k):
            if ops.analyze(1, h) != 0:
                failed += 1
            x1, x2 = ops.nodeDisp(1, 1), ops.nodeDisp(1, 2)
            r = float(np.hypot(x1, x2))
            if r > peak:
                peak, peak_dir = r, float(np.degrees(np.arctan2(x2, x1)))
        u[s + 1] = x1, x2
        for i in range(n):
            a_abs[s + 1, i] = ops.nodeAccel(i + 1, 1), ops.nodeAccel(i + 1, 2)
        a_abs[s + 1] += acc[:, s + 1]
        f = ops.eleResponse(1, "force")
        force[s + 1] = f[6], f[7]  # on the mat, global X and Y
        if spec["kind"] == "pendulum":
            # the normal force singleFPBearing's friction and restoring force use: the axial
            # force plus the shear's second-order term q·u/R (radii sqrt(R² − u_other²))
            qb = ops.eleResponse(1, "basicForce")
            r1, r2 = np.sqrt(R**2 - u[s + 1, 1] ** 2), np.sqrt(R**2 - u[s + 1, 0] ** 2)
            normal[s + 1] = -qb[0] + qb[1] * u[s + 1, 0] / r1 + qb[2] * u[s + 1, 1] / r2
    elapsed = time.perf_counter() - t0
    ops.wipe()
    return {
        "u": u.tolist(),
        "force": force.tolist(),
        "normal": normal.tolist(),
        "a_abs": a_abs.tolist(),
        "peak": peak,
        "peak_direction": peak_dir,
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


def _worker(python: str, spec: dict) -> dict:
    """Run one OpenSees analysis in `python` (``--worker``) and return its output."""
    proc = subprocess.run(
        [python, __file__, "--worker"],
        input=json.dumps(spec),
        capture_output=True,
        text=True,
        check=False,
    )
    if proc.returncode != 0:
        raise RuntimeError(f"OpenSees failed:\n{proc.stderr[-2000:]}")
    return json.loads(proc.stdout)


def _plane_row(
    name: str,
    method: str,
    peak: float,
    direction: float,
    u: np.ndarray,
    a: np.ndarray,
    elapsed: float,
    ref_exact: np.ndarray | None,
    ref_newmark: np.ndarray | None,
) -> None:
    """One markdown row of the bidirectional table.

    Parameters
    ----------
    name, method
        The bearing and the method.
    peak, direction
        ``max |u_b|`` (m) and its direction (degrees from ``h1`` towards ``h2``).
    u, a
        The bearing's displacement ``(npts, 2)`` and the floors' absolute accelerations
        ``(npts, n_dof, 2)`` at the samples.
    elapsed
        Wall time, s.
    ref_exact, ref_newmark
        Displacements to compare `u` with (``max_t |u − ref| / max_t |ref|``), or None.
    """

    def diff(ref):
        if ref is None:
            return "–"
        d, pk = np.hypot(*(u - ref).T).max(), np.hypot(*ref.T).max()
        return f"{d / pk:.1e}" if pk > 0 else f"{d:.1e} m (ref. 0)"

    roof = np.hypot(a[:, -1, 0], a[:, -1, 1]).max()
    print(
        f"| {name} | {method} | {peak:.5f} | {direction:7.2f} | "
        f"({u[-1, 0]:+.5f}, {u[-1, 1]:+.5f}) | {roof:.3f} | {diff(ref_exact)} | "
        f"{diff(ref_newmark)} | {elapsed:.4f} |"
    )


def main_plane(args: argparse.Namespace) -> int:
    """The bidirectional comparison (``--plane``): both bearings under a record pair, floorslide's
    exact coupled solver (pendulum) and 2-D Newmark beside OpenSees' 3-D model, a markdown table
    per record scale."""
    import floorslide as fs
    from floorslide.building.isolators import BilinearIsolator, FrictionPendulum
    from floorslide.building.nonlinear import NonlinearIsolatedBuilding
    from floorslide.building.nonlinear_approx import FRICTION_YIELD_DISP
    from floorslide.building.plane_isolation import plane_isolator_response
    from floorslide.building.plane_isolation_approx import newmark_plane_isolator_response
    from floorslide.records.pairs import read_pair

    pair = read_pair(*args.pair)
    dt = pair.dt
    n_s = min(args.samples, pair.h1.size)
    base = np.vstack([pair.h1[:n_s], pair.h2[:n_s]])
    if args.zero_start:
        base = np.hstack([np.zeros((2, 1)), base])
    sup = fs.ShearBuilding.from_period(stories=2, period=0.4, damping=0.03)
    cases = {
        "lead-rubber": BilinearIsolator(q_ratio=0.06, period=2.5, yield_disp=0.02),
        "pendulum": FrictionPendulum(mu=0.06, period=3.0),
    }
    t_all = time.perf_counter()
    for scale in args.scale:
        acc = scale * base
        h1, h2 = acc
        zero = ", a zero sample prepended" if args.zero_start else ""
        print(
            f"\n{Path(args.pair[0]).name} (h1) + {Path(args.pair[1]).name} (h2) × {scale:g}, "
            f"first {n_s} samples ({(n_s - 1) * dt:g} s){zero}, dt = {dt:g}; 2-storey "
            f"superstructure; roof PFA = max |a_roof| at the samples; direction at the peak "
            f"(fs Newmark: at its largest sample)\n"
        )
        print(
            "| bearing | method | peak \\|u_b\\| [m] | dir. [°] | residual (h1, h2) [m] | "
            "roof PFA [m/s²] | max\\|Δu_b\\|/peak vs exact | vs fs Newmark same dt/k | "
            "time [s] |"
        )
        print("|---|---|---|---|---|---|---|---|---|")
        notes = []
        for name, iso in cases.items():
            b = NonlinearIsolatedBuilding(sup, 1.0, iso)
            pendulum = isinstance(iso, FrictionPendulum)
            u_ex = None
            if pendulum:
                plane_isolator_response(b, h1[:20], h2[:20], dt)
                t0 = time.perf_counter()
                ex = plane_isolator_response(b, h1, h2, dt)
                t_ex = time.perf_counter() - t0
                u_ex = ex.displacement
                _plane_row(
                    name, "floorslide exact", ex.peak_displacement, ex.peak_direction, u_ex,
                    ex.floor_acceleration, t_ex, u_ex, None,
                )  # fmt: skip
                notes += [f"{name}, exact: {note}" for note in ex.notes]
            spec = {
                "kind": "pendulum" if pendulum else "bilinear",
                "mass": b.mass.tolist(),
                "Ks": sup.stiffness_matrix.tolist(),
                "Cs": sup.damping_matrix.tolist(),
                "constants": {key: float(v) for key, v in b.constants.items()},
                "friction_yield": FRICTION_YIELD_DISP,
                "acc": acc.tolist(),
                "dt": dt,
                "plane": True,
            }
            for k in args.substeps:
                kw = {"substeps": k, "friction_yield": FRICTION_YIELD_DISP}
                newmark_plane_isolator_response(b, h1[:20], h2[:20], dt, **kw)
                nm = newmark_plane_isolator_response(b, h1, h2, dt, **kw)
                u_nm = nm.displacement
                i = np.hypot(*u_nm.T).argmax()  # its direction: at the largest sample
                _plane_row(
                    name, f"fs Newmark dt/{k}", nm.peak_displacement,
                    float(np.degrees(np.arctan2(u_nm[i, 1], u_nm[i, 0]))), u_nm,
                    nm.floor_acceleration, nm.elapsed, u_ex, None,
                )  # fmt: skip
                spec["substeps"] = k
                try:
                    out = _worker(args.opensees_python, spec)
                    ctl = None
                    if pendulum and args.control:
                        ctl = _worker(args.opensees_python, {**spec, "kind": "flat"})
                except RuntimeError as err:
                    print(err)
                    return 1
                u = np.asarray(out["u"])
                _plane_row(
                    name, f"OpenSees dt/{k}", out["peak"], out["peak_direction"], u,
                    np.asarray(out["a_abs"]), out["elapsed"], u_ex, u_nm,
                )  # fmt: skip
                if out["failed"]:
                    notes.append(f"{name}, OpenSees dt/{k}: {out['failed']} steps failed")
                if ctl is not None:
                    _plane_row(
                        name, f"OpenSees flat+spring dt/{k}", ctl["peak"], ctl["peak_direction"],
                        np.asarray(ctl["u"]), np.asarray(ctl["a_abs"]), ctl["elapsed"], u_ex,
                        u_nm,
                    )  # fmt: skip
                    if ctl["failed"]:
                        notes.append(f"{name}, control dt/{k}: {ctl['failed']} steps failed")
                c = b.constants
                f = np.asarray(out["force"])
                if pendulum:
                    nn = np.asarray(out["normal"])[1:] / c["W"]
                    notes.append(
                        f"{name}, OpenSees dt/{k}: normal force W + q·u/R between "
                        f"{nn.min():.4f} W and {nn.max():.4f} W (floorslide: W)"
                    )
                else:
                    env = np.hypot(*(f - c["k2"] * u).T).max() / c["Q"]
                    notes.append(
                        f"{name}, OpenSees dt/{k}: force envelope max|f − k2·u|/Q = {env:.6f}"
                    )
        print()
        for note in notes:
            print(f"- {note}")
    print(f"\ntotal wall time {time.perf_counter() - t_all:.1f} s")
    return 0


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
    p.add_argument(
        "--plane",
        action="store_true",
        help="bidirectional mode: a record pair on the 3-D model (instead of El Centro in 1-D)",
    )
    p.add_argument(
        "--pair",
        nargs=2,
        metavar=("H1", "H2"),
        default=[
            str(PAIRS / "RSN1084_NORTHR_SCS052.AT2"),
            str(PAIRS / "RSN1084_NORTHR_SCS142.AT2"),
        ],
        help="--plane: the two horizontal components (PEER .AT2 or any read_pair input)",
    )
    p.add_argument("--samples", type=int, default=3000, help="--plane: samples of the pair used")
    p.add_argument(
        "--scale", type=float, nargs="+", default=[1.0, 0.3], help="--plane: record scales"
    )
    p.add_argument(
        "--control",
        action=argparse.BooleanOptionalAction,
        default=True,
        help="--plane: also the pendulum as flatSliderBearing + a spring W/R (floorslide's model)",
    )
    p.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    args = p.parse_args(argv)
    if args.worker:
        spec = json.load(sys.stdin)
        run = run_opensees_plane if spec.get("plane") else run_opensees
        json.dump(run(spec), sys.stdout)
        return 0
    if args.plane:
        return main_plane(args)

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
            try:
                out = _worker(args.opensees_python, spec)
            except RuntimeError as err:
                print(err)
                return 1
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

#!/usr/bin/env python3
"""Reads nendo's one-surface STEP and IGES exports (`nendo export --one-surface`) with OpenCASCADE
and checks them against the model's patches.

Usage: cad_one_surface.py MODEL.json FILE.step FILE.igs [MM_PER_MODEL_UNIT]

The knots are derived here from the model's saved spacing ratios, independently of nendo's Rust
code: widths h_0 = 1, h_k = rho_k h_(k-1), scaled to sum to the patch count; patch (iu, iv)'s
point (s, t) is the spline's point at (U_iu + s h_iu, V_iv + t h_iv). MM_PER_MODEL_UNIT (default 1)
is what OCC's millimetres should be per model unit (the export's --scale times its unit).

STEP: BRepCheck_Analyzer valid; exactly one face, a non-rational B-spline surface of degree 3x3
with (2M+2) x (2N+2) poles and knots at the break points (multiplicities 4, 2, ..., 2, 4; a
closed direction may come out periodic, 2M+1 poles, the seam knot triple), whose
points agree with every patch to 1e-9 (relative to the scale) at 5 x 5 parameters per patch;
the face FORWARD with nendo's normal; sphere and torus one closed solid with the exact volume
(divergence theorem over the patches) to 1e-6 relative, open topologies one open shell.
IGES: one top-level entity (the group, 402), one valid face on the same surface.

Exits 1 with a message naming what failed.
"""

import json
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cad_check import (Failure, exact_volume, explore, fail, load_model, one_root,  # noqa: E402
                       patch_frame, patch_point, read, occ_normal)

from OCP.BRep import BRep_Tool  # noqa: E402
from OCP.BRepCheck import BRepCheck_Analyzer  # noqa: E402
from OCP.BRepGProp import BRepGProp  # noqa: E402
from OCP.GProp import GProp_GProps  # noqa: E402
from OCP.IGESControl import IGESControl_Reader  # noqa: E402
from OCP.STEPControl import STEPControl_Reader  # noqa: E402
from OCP.TopAbs import TopAbs_FACE, TopAbs_FORWARD, TopAbs_SHELL, TopAbs_SOLID  # noqa: E402
from OCP.TopoDS import TopoDS  # noqa: E402

POINT_TOL = 1e-9
VOLUME_REL = 1e-6


def breaks(ratios, count):
    widths, h = [], 1.0
    for k in range(count):
        if k > 0:
            h *= ratios[k]
        widths.append(h)
    scale = count / sum(widths)
    b = [0.0]
    for w in widths:
        b.append(b[-1] + w * scale)
    return np.array(b)


def the_face(shape, path, m, n, bu, bv):
    faces = list(explore(shape, TopAbs_FACE))
    if len(faces) != 1:
        fail(f"{path}: {len(faces)} faces, expected one")
    face = TopoDS.Face(faces[0])
    srf = BRep_Tool.Surface_s(face)
    if type(srf).__name__ != "Geom_BSplineSurface":
        fail(f"{path}: the face's surface is {type(srf).__name__}, not a B-spline surface")
    # A closed direction may come out periodic: OCC's reader turns a closed clamped spline
    # into a periodic one keeping the seam knot triple (2M + 1 poles), the same surface.
    got = (srf.UDegree(), srf.VDegree())
    if got != (3, 3):
        fail(f"{path}: degree {got}, expected 3x3")
    if srf.IsURational() or srf.IsVRational():
        fail(f"{path}: the surface is rational")
    for name, count, nb, knot, mult, periodic, poles, want in [
            ("u", m, srf.NbUKnots(), srf.UKnot, srf.UMultiplicity, srf.IsUPeriodic(),
             srf.NbUPoles(), bu),
            ("v", n, srf.NbVKnots(), srf.VKnot, srf.VMultiplicity, srf.IsVPeriodic(),
             srf.NbVPoles(), bv)]:
        ks = np.array([knot(i) for i in range(1, nb + 1)])
        ms = [mult(i) for i in range(1, nb + 1)]
        if len(ks) != len(want) or np.max(np.abs(ks - want)) > 1e-12 * len(want):
            fail(f"{path}: {name} knots {ks[:6]}... are not the break points {want[:6]}...")
        if periodic:
            expect = (2 * count + 1, [3] + [2] * (len(want) - 2) + [3])
        else:
            expect = (2 * count + 2, [4] + [2] * (len(want) - 2) + [4])
        if (poles, ms) != expect:
            fail(f"{path}: {name}: {poles} poles, multiplicities {ms[:6]}..., expected "
                 f"{expect[0]} and {expect[1][:6]}... ({'periodic' if periodic else 'clamped'})")
    return face, srf


def check_points(srf, patches, m, bu, bv, scale, path):
    worst = 0.0
    ts = np.linspace(0, 1, 5)
    for k, P in enumerate(patches):
        iu, iv = k % m, k // m
        for s in ts:
            for t in ts:
                u = bu[iu] + s * (bu[iu + 1] - bu[iu])
                v = bv[iv] + t * (bv[iv + 1] - bv[iv])
                q = srf.Value(u, v)
                d = np.linalg.norm(np.array([q.X(), q.Y(), q.Z()]) - scale * patch_point(P, s, t))
                worst = max(worst, d)
    if worst > POINT_TOL * scale:
        fail(f"{path}: the surface is {worst:.3e} from the patches (> {POINT_TOL * scale:.1e})")
    return worst


def main():
    if len(sys.argv) not in (4, 5):
        sys.exit("usage: cad_one_surface.py MODEL.json FILE.step FILE.igs [MM_PER_MODEL_UNIT]")
    model, step, iges = sys.argv[1:4]
    scale = float(sys.argv[4]) if len(sys.argv) == 5 else 1.0
    try:
        topology, m, n, patches = load_model(model)
        with open(model) as f:
            ratios = json.load(f)["surface"]["ratios"]
        bu, bv = breaks(ratios["u"], m), breaks(ratios["v"], n)

        shape = read(STEPControl_Reader(), step)
        if not BRepCheck_Analyzer(shape).IsValid():
            fail(f"{step}: BRepCheck_Analyzer: the shape is not valid")
        face, srf = the_face(shape, step, m, n, bu, bv)
        worst = check_points(srf, patches, m, bu, bv, scale, step)
        if face.Orientation() != TopAbs_FORWARD:
            fail(f"{step}: the face came out {face.Orientation()} (OCC turned it)")
        for k in (0, len(patches) // 2, len(patches) - 1):
            iu, iv = k % m, k // m
            u, v = (bu[iu] + bu[iu + 1]) / 2, (bv[iv] + bv[iv + 1]) / 2
            _, Su, Sv = patch_frame(patches[k], 0.5, 0.5)
            got = occ_normal(face, u, v)
            if got is None or np.dot(got, np.cross(Su, Sv)) <= 0:
                fail(f"{step}: the normal on patch {k} is not nendo's S_u x S_v")
        solids = list(explore(shape, TopAbs_SOLID))
        shells = list(explore(shape, TopAbs_SHELL))
        if len(shells) != 1:
            fail(f"{step}: {len(shells)} shells, expected 1")
        what = "open shell"
        if topology in ("sphere", "torus"):
            if len(solids) != 1 or not BRep_Tool.IsClosed_s(shells[0]):
                fail(f"{step}: {len(solids)} solids, expected one closed solid")
            props = GProp_GProps()
            BRepGProp.VolumeProperties_s(solids[0], props, 1e-10)
            got, want = props.Mass(), exact_volume(patches) * scale ** 3
            if not got > 0 or abs(got - want) > VOLUME_REL * abs(want):
                fail(f"{step}: volume {got!r}, exact {want!r}")
            what = (f"closed solid, volume {got:.9g} (exact {want:.9g}, rel. error "
                    f"{abs(got - want) / want:.1e})")
        elif solids:
            fail(f"{step}: an open {topology} came out as a solid")
        form = "x".join(("periodic " if p else "") + str(k) for p, k in
                        [(srf.IsUPeriodic(), srf.NbUPoles()), (srf.IsVPeriodic(), srf.NbVPoles())])
        print(f"{step}: valid {what}, one face: B-spline 3x3 with {form} poles "
              f"on the ratios' knots, {worst:.1e} from the {len(patches)} patches")

        one_root(IGESControl_Reader(), iges)
        shape = read(IGESControl_Reader(), iges)
        if not BRepCheck_Analyzer(shape).IsValid():
            fail(f"{iges}: BRepCheck_Analyzer: the shape is not valid")
        face, srf = the_face(shape, iges, m, n, bu, bv)
        worst = check_points(srf, patches, m, bu, bv, scale, iges)
        print(f"{iges}: valid, one group, one face on the same surface, {worst:.1e} from the "
              f"patches")
    except Failure as e:
        sys.exit(f"cad check FAILED: {e}")


if __name__ == "__main__":
    main()

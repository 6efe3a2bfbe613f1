#!/usr/bin/env python3
"""Reads nendo's STEP and IGES exports with OpenCASCADE (OCP) and checks them against the model.

Usage: cad_check.py MODEL.json FILE.step FILE.igs

Everything on nendo's side is computed here from the model JSON's control points, independently
of nendo's Rust code: points by de Casteljau, normals from the Bernstein derivatives, the exact
enclosed volume by the divergence theorem, V = (1/3) sum over patches of the integral of
P . (S_u x S_v) du dv, with Gauss-Legendre quadrature of 8 points per direction (exact: the
integrand is a polynomial of degree 8 in u and in v).

STEP checks: BRepCheck_Analyzer valid; one face per patch; each face a B-spline surface of degree
3x3 whose 16 poles are the patch's control points and whose points agree with the patch to 1e-9;
closed topologies (sphere, torus) one closed solid whose volume is positive and equal to the
exact volume to 1e-6 relative; open ones one shell whose free boundary has one closed loop per
open border; every non-degenerate edge shared by exactly two faces except the border edges
(counted from the grid); G1 across every shared edge as read by OCC (normals sampled on both faces
along the edge) within 0.01 degrees; every face oriented outward as written: OCC's faces all
FORWARD as explored from the shape (its shape healing flips a face or a whole shell it finds
reversed, which would show as REVERSED here) with normals that agree with nendo's S_u x S_v, and,
read from the file's own data with a small parser (no healing at all), every ADVANCED_FACE is
same-sense with its loop running counter-clockwise in (u, v) from the surface's corner P00 (a pole
side left out, as OCC writes it: no zero-length edges), and each shared EDGE_CURVE is used once in
each direction.

IGES checks: one top-level entity (the group, 402), one face per patch, each a B-spline surface of degree 3x3 with the patch's control
points and points that agree to 1e-9, BRepCheck_Analyzer valid (IGES gets no topology: no shell).

Both: each model curve is one free edge whose B-spline has the curve's degree, knots and control
points exactly (a Bezier curve on its (d+1)-fold knots 0 and 1, a planar curve at z = 0).

Exits 1 with a message naming what failed.
"""

import json
import math
import re
import sys

import numpy as np

try:
    from OCP.BRep import BRep_Tool
    from OCP.BRepAdaptor import BRepAdaptor_Curve2d
    from OCP.BRepCheck import BRepCheck_Analyzer
    from OCP.BRepGProp import BRepGProp
    from OCP.GProp import GProp_GProps
    from OCP.gp import gp_Pnt, gp_Vec
    from OCP.IFSelect import IFSelect_RetDone
    from OCP.IGESControl import IGESControl_Reader
    from OCP.ShapeAnalysis import ShapeAnalysis_FreeBounds
    from OCP.STEPControl import STEPControl_Reader
    from OCP.TopAbs import (TopAbs_EDGE, TopAbs_FACE, TopAbs_FORWARD, TopAbs_REVERSED,
                            TopAbs_SHELL, TopAbs_SOLID, TopAbs_WIRE)
    from OCP.TopExp import TopExp, TopExp_Explorer
    from OCP.TopoDS import TopoDS
    # 8.0 moved the collection classes into OCP.collections.
    from OCP.collections import (
        IndexedDataMap_TopoDS_Shape_List_TopoDS_Shape_TopTools_ShapeMapHasher as EdgeFaceMap)
except ImportError as e:  # the check must never pass without OpenCASCADE
    sys.exit(f"cad check FAILED: OpenCASCADE (PyPI cadquery-ocp-novtk) cannot be imported: {e}")

POINT_TOL = 1e-9
VOLUME_REL = 1e-6
G1_DEG = 0.01


class Failure(Exception):
    pass


def fail(msg):
    raise Failure(msg)


# ---------------------------------------------------------------- nendo's side, independently

def bernstein(t):
    s = 1.0 - t
    return np.array([s * s * s, 3 * t * s * s, 3 * t * t * s, t * t * t])


def bernstein_d(t):
    s = 1.0 - t
    return np.array([-3 * s * s, 3 * s * s - 6 * t * s, 6 * t * s - 3 * t * t, 3 * t * t])


def casteljau(points, t):
    pts = [np.asarray(p, dtype=float) for p in points]
    while len(pts) > 1:
        pts = [(1 - t) * a + t * b for a, b in zip(pts, pts[1:])]
    return pts[0]


def patch_point(P, u, v):
    """P[i][j] (i along u): de Casteljau along v in each row, then along u."""
    return casteljau([casteljau(P[i], v) for i in range(4)], u)


def patch_frame(P, u, v):
    bu, bv, du, dv = bernstein(u), bernstein(v), bernstein_d(u), bernstein_d(v)
    S = np.einsum("i,j,ijk->k", bu, bv, P)
    Su = np.einsum("i,j,ijk->k", du, bv, P)
    Sv = np.einsum("i,j,ijk->k", bu, dv, P)
    return S, Su, Sv


def exact_volume(patches):
    x, w = np.polynomial.legendre.leggauss(8)
    t, w = (x + 1) / 2, w / 2
    total = 0.0
    for P in patches:
        for a, wu in zip(t, w):
            for b, wv in zip(t, w):
                S, Su, Sv = patch_frame(P, a, b)
                total += wu * wv * np.dot(S, np.cross(Su, Sv))
    return total / 3.0


def load_model(path):
    with open(path) as f:
        doc = json.load(f)
    s = doc["surface"]
    patches = [np.array(p, dtype=float).reshape(4, 4, 3) for p in s["patches"]]
    return s["topology"], s["patches_u"], s["patches_v"], patches


def load_curves(path):
    """The model's curves as (degree, knot vector, 3D control points): a Bezier curve of degree
    d on d+1 zeros and d+1 ones, a planar curve at z = 0."""
    with open(path) as f:
        doc = json.load(f)
    out = []
    for c in doc.get("curves", []):
        if "bezier" in c:
            pts = c["bezier"]
            d = len(pts) - 1
            knots = [0.0] * (d + 1) + [1.0] * (d + 1)
        else:
            pts, d, knots = c["bspline"]["points"], c["bspline"]["degree"], c["bspline"]["knots"]
        pts = np.array([list(p) + [0.0] * (3 - len(p)) for p in pts], dtype=float)
        out.append((d, [float(k) for k in knots], pts))
    return out


def check_curves(shape, model_path, path):
    """Every model curve is one free edge (in no face) whose curve is a B-spline of the same
    degree, knots and control points."""
    want = load_curves(model_path)
    got = []
    for e in explore_free_edges(shape):
        c = BRep_Tool.Curve_s(TopoDS.Edge(e), 0.0, 1.0)
        if type(c).__name__ != "Geom_BSplineCurve":
            fail(f"{path}: a curve came out as {type(c).__name__}, not a B-spline")
        knots = []
        for i in range(1, c.NbKnots() + 1):
            knots += [c.Knot(i)] * c.Multiplicity(i)
        pts = np.array([[c.Pole(i).X(), c.Pole(i).Y(), c.Pole(i).Z()]
                        for i in range(1, c.NbPoles() + 1)])
        got.append((c.Degree(), knots, pts))
    if len(got) != len(want):
        fail(f"{path}: {len(got)} free curves for the model's {len(want)} curves")
    for k, (d, knots, pts) in enumerate(want):
        if not any(g[0] == d and g[1] == knots and g[2].shape == pts.shape
                   and np.array_equal(g[2], pts) for g in got):
            fail(f"{path}: curve {k} (degree {d}, {len(pts)} points) is not among the "
                 f"B-spline curves read back with its degree, knots and control points")
    return len(want)


def explore_free_edges(shape):
    e = TopExp_Explorer(shape, TopAbs_EDGE, TopAbs_FACE)
    while e.More():
        yield e.Current()
        e.Next()


def border_edges(topology, m, n):
    """Non-degenerate patch sides on an open border."""
    return {"plane": 2 * m + 2 * n, "cylinder": 2 * m, "hemisphere": m,
            "sphere": 0, "torus": 0}[topology]


def open_borders(topology):
    return {"plane": 1, "cylinder": 2, "hemisphere": 1, "sphere": 0, "torus": 0}[topology]


# ---------------------------------------------------------------- OCC helpers

def explore(shape, kind):
    e = TopExp_Explorer(shape, kind)
    while e.More():
        yield e.Current()
        e.Next()


def read(reader, path):
    if reader.ReadFile(path) != IFSelect_RetDone:
        fail(f"{path}: OCC cannot read the file")
    reader.TransferRoots()
    shape = reader.OneShape()
    if shape.IsNull():
        fail(f"{path}: OCC transferred no shape")
    return shape


def bspline(face, path):
    srf = BRep_Tool.Surface_s(face)
    if type(srf).__name__ != "Geom_BSplineSurface":
        fail(f"{path}: a face's surface is {type(srf).__name__}, not a B-spline surface")
    if (srf.UDegree(), srf.VDegree(), srf.NbUPoles(), srf.NbVPoles()) != (3, 3, 4, 4):
        fail(f"{path}: a surface is of degree {srf.UDegree()}x{srf.VDegree()} with "
             f"{srf.NbUPoles()}x{srf.NbVPoles()} poles, not 3x3 with 4x4")
    if srf.IsURational() or srf.IsVRational():
        for i in range(1, 5):
            for j in range(1, 5):
                if srf.Weight(i, j) != 1.0:
                    fail(f"{path}: a surface has weight {srf.Weight(i, j)}")
    return srf


def poles(srf):
    return np.array([[[srf.Pole(i, j).X(), srf.Pole(i, j).Y(), srf.Pole(i, j).Z()]
                      for j in range(1, 5)] for i in range(1, 5)])


def match_faces(shape, patches, path):
    """Each face to its patch by its poles (exactly the model's control points)."""
    by_points = {tuple(np.round(P, 12).ravel()): k for k, P in enumerate(patches)}
    faces = list(explore(shape, TopAbs_FACE))
    if len(faces) != len(patches):
        fail(f"{path}: {len(faces)} faces for {len(patches)} patches")
    matched = {}
    for f in faces:
        face = TopoDS.Face(f)
        srf = bspline(face, path)
        u0, u1, v0, v1 = srf.Bounds()
        if (u0, u1, v0, v1) != (0.0, 1.0, 0.0, 1.0):
            fail(f"{path}: a surface's parameter range is {(u0, u1, v0, v1)}, not [0,1]^2")
        key = tuple(np.round(poles(srf), 12).ravel())
        k = by_points.get(key)
        if k is None:
            fail(f"{path}: a face's poles are not any patch's control points")
        if k in matched:
            fail(f"{path}: patch {k} appears twice")
        P = patches[k]
        if np.max(np.abs(poles(srf) - P)) != 0.0:
            fail(f"{path}: patch {k}'s poles differ from its control points "
                 f"by {np.max(np.abs(poles(srf) - P)):.3e}")
        worst = 0.0
        for u in np.linspace(0, 1, 7):
            for v in np.linspace(0, 1, 7):
                q = srf.Value(u, v)
                worst = max(worst, np.linalg.norm(np.array([q.X(), q.Y(), q.Z()])
                                                  - patch_point(P, u, v)))
        if worst > POINT_TOL:
            fail(f"{path}: patch {k}: OCC's surface is {worst:.3e} from nendo's patch (> 1e-9)")
        matched[k] = face
    return matched


def occ_normal(face, u, v):
    srf = BRep_Tool.Surface_s(face)
    p, du, dv = gp_Pnt(), gp_Vec(), gp_Vec()
    srf.D1(u, v, p, du, dv)
    n = np.cross([du.X(), du.Y(), du.Z()], [dv.X(), dv.Y(), dv.Z()])
    if face.Orientation() == TopAbs_REVERSED:
        n = -n
    length = np.linalg.norm(n)
    return n / length if length > 0 else None


# ---------------------------------------------------------------- the file's own data

ENTITY = re.compile(r"^#(\d+)=(.*);$")


def step_entities(path):
    ents = {}
    with open(path) as f:
        text = f.read()
    data = text.split("DATA;", 1)[1].rsplit("ENDSEC;", 1)[0]
    for line in data.strip().splitlines():
        m = ENTITY.match(line.strip())
        if not m:
            fail(f"{path}: cannot parse {line[:60]!r}")
        ents[int(m.group(1))] = m.group(2)
    return ents


def refs(body):
    return [int(x) for x in re.findall(r"#(\d+)", body)]


def orientation_from_file(path, topology):
    """Face orientation as written, no healing: same sense, loop counter-clockwise in (u, v)
    from the surface's corner P00 along v = 0, each shared edge used once each way."""
    ents = step_entities(path)
    uses = {}
    point = {}
    for k, body in ents.items():
        if body.startswith("CARTESIAN_POINT("):
            point[k] = tuple(float(x) for x in re.findall(r"[-+0-9.E]+", body.split(",", 1)[1]))
    faces = [(k, b) for k, b in ents.items() if b.startswith("ADVANCED_FACE(")]
    for k, body in faces:
        if not body.endswith(",.T.)"):
            fail(f"{path}: face #{k} is not same-sense")
        bound, surface = refs(body)
        surf_pts = refs(ents[surface])
        p00, p30 = surf_pts[0], surf_pts[12]
        loop = refs(ents[bound])[0]
        oes = refs(ents[loop])
        # A side collapsed into a pole is left out (OCC's own style): three edges, and the
        # loop then starts along u = 1 from the pole P00 = P30 when the pole is at v = 0.
        pole_at_start = point[p00] == point[p30]
        pole_at_end = point[surf_pts[3]] == point[surf_pts[15]]
        if len(oes) != 4 - pole_at_start - pole_at_end:
            fail(f"{path}: face #{k} has {len(oes)} edges in its loop")
        if pole_at_start:
            p00, p30 = surf_pts[12], surf_pts[15]
        starts = []
        for oe in oes:
            body_oe = ents[oe]
            edge = refs(body_oe)[0]
            forward = body_oe.endswith(".T.)")
            v0, v1, curve, = refs(ents[edge])
            if len(set(point[p] for p in refs(ents[curve]))) == 1:
                fail(f"{path}: face #{k} has a zero-length edge (a pole side written out)")
            uses.setdefault(edge, []).append(forward)
            a, b = (v0, v1) if forward else (v1, v0)
            starts.append((refs(ents[a])[0], refs(ents[b])[0]))
        # The first oriented edge runs from P00 to P30 (v = 0, increasing u; from P30 to P33
        # at a pole at v = 0), and the loop is connected head to tail.
        if point[starts[0][0]] != point[p00] or point[starts[0][1]] != point[p30]:
            fail(f"{path}: face #{k}'s loop does not start along v = 0 from P00 to P30")
        for (a, b), (c, _) in zip(starts, starts[1:] + starts[:1]):
            if point[b] != point[c]:
                fail(f"{path}: face #{k}'s loop is not connected")
    for edge, senses in uses.items():
        if len(senses) == 2 and sorted(senses) != [False, True]:
            fail(f"{path}: edge #{edge} is used twice in the same direction (a face is reversed)")
        if len(senses) > 2:
            fail(f"{path}: edge #{edge} is used {len(senses)} times")
    shared = sum(1 for s in uses.values() if len(s) == 2)
    return len(faces), shared


# ---------------------------------------------------------------- the checks

def check_step(model_path, path, report):
    topology, m, n, patches = load_model(model_path)
    shape = read(STEPControl_Reader(), path)
    if not BRepCheck_Analyzer(shape).IsValid():
        fail(f"{path}: BRepCheck_Analyzer: the shape is not valid")
    faces = match_faces(shape, patches, path)
    closed = topology in ("sphere", "torus")

    # Outward as written: no face turned by OCC, normals as nendo's.
    for k, face in faces.items():
        if face.Orientation() != TopAbs_FORWARD:
            fail(f"{path}: patch {k}'s face came out {face.Orientation()} (OCC turned it)")
        for u, v in [(0.3, 0.4), (0.5, 0.5), (0.7, 0.6)]:
            _, Su, Sv = patch_frame(patches[k], u, v)
            want = np.cross(Su, Sv)
            got = occ_normal(face, u, v)
            if got is None or np.dot(got, want) <= 0:
                fail(f"{path}: patch {k}'s face normal is not nendo's S_u x S_v")
    file_faces, file_shared = orientation_from_file(path, topology)

    # Topology: shells, solids, sharing.
    solids = list(explore(shape, TopAbs_SOLID))
    shells = list(explore(shape, TopAbs_SHELL))
    if len(shells) != 1:
        fail(f"{path}: {len(shells)} shells, expected 1")
    edge_faces = EdgeFaceMap()
    TopExp.MapShapesAndAncestors_s(shape, TopAbs_EDGE, TopAbs_FACE, edge_faces)
    shared, border, degenerate = [], 0, 0
    for i in range(1, edge_faces.Extent() + 1):
        edge = TopoDS.Edge(edge_faces.FindKey(i))
        users = edge_faces.FindFromIndex(i)
        count = users.Size()
        if count == 0:
            continue  # a model curve (checked by check_curves)
        if BRep_Tool.Degenerated_s(edge):
            degenerate += 1
        elif count == 2:
            shared.append((edge, [TopoDS.Face(f) for f in users]))
        elif count == 1:
            border += 1
        else:
            fail(f"{path}: an edge is used by {count} faces")
    if border != border_edges(topology, m, n):
        fail(f"{path}: {border} free edges, expected {border_edges(topology, m, n)} "
             f"(the open borders of a {topology})")
    if len(shared) != file_shared:
        fail(f"{path}: OCC shares {len(shared)} edges, the file {file_shared}")
    free = ShapeAnalysis_FreeBounds(shape, 1e-7, False, False)
    loops = len(list(explore(free.GetClosedWires(), TopAbs_WIRE)))
    open_wires = len(list(explore(free.GetOpenWires(), TopAbs_WIRE)))
    if loops != open_borders(topology) or open_wires != 0:
        fail(f"{path}: free boundary of {loops} closed and {open_wires} open loops, "
             f"expected {open_borders(topology)} closed")
    volume_text = ""
    if closed:
        if len(solids) != 1:
            fail(f"{path}: {len(solids)} solids, expected 1 closed solid")
        if not BRep_Tool.IsClosed_s(shells[0]):
            fail(f"{path}: the shell is not closed")
        props = GProp_GProps()
        BRepGProp.VolumeProperties_s(solids[0], props, 1e-10)
        got, want = props.Mass(), exact_volume(patches)
        if not got > 0:
            fail(f"{path}: the solid's volume is {got} (inside out)")
        if abs(got - want) > VOLUME_REL * abs(want):
            fail(f"{path}: volume {got!r}, exact {want!r}: relative error "
                 f"{abs(got - want) / abs(want):.2e} > 1e-6")
        volume_text = f", volume {got:.9g} (exact {want:.9g}, rel. error {abs(got - want) / want:.1e})"
    elif solids:
        fail(f"{path}: an open {topology} came out as a solid")

    # G1 across shared edges, as OCC reads them.
    worst = 0.0
    for edge, (f1, f2) in shared:
        c1, c2 = BRepAdaptor_Curve2d(edge, f1), BRepAdaptor_Curve2d(edge, f2)
        a, b = c1.FirstParameter(), c1.LastParameter()
        for s in np.linspace(0.02, 0.98, 9):
            t = a + s * (b - a)
            # The same 3D point on both faces (the pcurves share the edge's parameter).
            p1, p2 = c1.Value(t), c2.Value(t)
            n1, n2 = occ_normal(f1, p1.X(), p1.Y()), occ_normal(f2, p2.X(), p2.Y())
            if n1 is None or n2 is None:
                continue
            angle = math.degrees(math.acos(max(-1.0, min(1.0, float(np.dot(n1, n2))))))
            worst = max(worst, angle)
    if worst > G1_DEG:
        fail(f"{path}: normals across a shared edge differ by {worst:.4g} degrees (> 0.01)")
    curves = check_curves(shape, model_path, path)
    report.append(
        f"{path}: valid {'closed solid' if closed else 'open shell'}, {len(faces)} faces "
        f"(B-spline 3x3, poles = control points, points within 1e-9), {len(shared)} shared "
        f"edges, {border} border edges in {loops} loop(s), {degenerate} degenerate (pole) edges"
        f"{volume_text}, G1 worst {worst:.2e} deg, all faces forward and outward as written"
        f" ({file_faces} same-sense faces in the file), {curves} curves exact")


def one_root(reader, path):
    """The file's entities are in one group (entity 402): one root to transfer."""
    if reader.ReadFile(path) != IFSelect_RetDone:
        fail(f"{path}: OCC cannot read the file")
    roots = reader.NbRootsForTransfer()
    if roots != 1:
        fail(f"{path}: {roots} top-level entities, expected 1 (the group, entity 402)")


def check_iges(model_path, path, report):
    topology, m, n, patches = load_model(model_path)
    one_root(IGESControl_Reader(), path)
    shape = read(IGESControl_Reader(), path)
    if not BRepCheck_Analyzer(shape).IsValid():
        fail(f"{path}: BRepCheck_Analyzer: the shape is not valid")
    faces = match_faces(shape, patches, path)
    curves = check_curves(shape, model_path, path)
    report.append(f"{path}: valid, one group, {len(faces)} faces (B-spline 3x3, poles = control "
                  f"points, points within 1e-9), {curves} curves exact")


def main():
    if len(sys.argv) != 4:
        sys.exit("usage: cad_check.py MODEL.json FILE.step FILE.igs")
    model, step, iges = sys.argv[1:]
    report = []
    try:
        check_step(model, step, report)
        check_iges(model, iges, report)
    except Failure as e:
        sys.exit(f"cad check FAILED: {e}")
    for line in report:
        print(line)


if __name__ == "__main__":
    main()

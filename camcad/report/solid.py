"""The cam as a solid through a CAD kernel: cam.step (exact B-spline faces) and cam.stl (a watertight mesh).

The kernel is Open CASCADE through its Python binding OCP (``pip install 'camcad[solid]'``, the package
cadquery-ocp-novtk: the kernel alone, without VTK; docs/part.md says why this one). It is imported only when a
solid is asked for; without it one line says what to install (exit 2).

A flank's outline is the clamped cubic B-spline of ``camcad.profile.toolpath.outline_spline`` (within the
chord tolerance of the exact flank, in the cam angle), made into kernel edges of at most ``SPANS_PER_EDGE``
spans each, split where the law's pieces meet: the kernel's volume integration is exact to 1e-7 on such
faces, and loses 0.1 % on one face of 500 spans (measured on the default cam: 80312.7 against 80411.2 mm³).
The plate is that outline extruded by the thickness, less the bore (a circle) and the keyway (a slot of
width W from the bore's centre line to H beyond the bore, on the cam's +y axis: the follower's side at cam
angle 0); a groove cam is a disc with the groove (between its two flanks) cut to the depth of cut from the
top face.

STEP: AP214, the length unit mm or inch, written with a fixed time stamp and the design's name, so the same
design gives the same bytes. STL: binary, the kernel's mesh within the chord tolerance (linear deflection),
every vertex shared by the faces that meet there (a closed, watertight mesh); the unit is in the header.
"""

from __future__ import annotations

import itertools
import math
import re
import struct
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from camcad.errors import CamcadError
from camcad.profile.synth import ProfileResult
from camcad.profile.toolpath import Flank, flanks, outline_spline, part_ready
from camcad.version import __version__

#: spans of the B-spline per kernel edge (and so per side face of the solid) at most
SPANS_PER_EDGE = 32
#: mm per inch
INCH_MM = 25.4
#: the time stamp written into every STEP file (ISO 8601), so that the same design gives the same file
STEP_TIME_STAMP = "2000-01-01T00:00:00"
#: what to install for the solids
INSTALL_HINT = "pip install 'camcad[solid]' (the Open CASCADE kernel, package cadquery-ocp-novtk)"


def kernel():
    """The OCP modules the solids need, or a CamcadError saying what to install (exit 2)."""
    try:
        from OCP import (  # noqa: F401 - imported to see that the kernel is there
            BRep,
            BRepAlgoAPI,
            BRepBuilderAPI,
            BRepPrimAPI,
            Geom,
            gp,
        )
    except ImportError:
        raise CamcadError("cam.step and cam.stl need the optional CAD kernel, which is not installed",
                          "--export step/stl", INSTALL_HINT) from None
    import OCP

    _quiet()
    return OCP


def _quiet() -> None:
    """The kernel's messages (its STEP writer's statistics go to standard output) kept to failures only."""
    from OCP.Message import Message, Message_Gravity

    printers = Message.DefaultMessenger_s().Printers()
    for i in range(1, printers.Length() + 1):
        printers.Value(i).SetTraceLevel(Message_Gravity.Message_Fail)


@dataclass(frozen=True)
class PartShape:
    """A solid made by the kernel (mm) and what it is made of."""

    part: str
    shape: object
    thickness: float
    bore: float | None
    keyway: tuple[float, float] | None
    plate: float | None
    groove_depth: float | None
    max_deviation: float
    notes: tuple[str, ...]


def _edges_of(spline, joints: np.ndarray):
    """Kernel edges of the clamped cubic B-spline (mm, knots in rad), ≤ SPANS_PER_EDGE spans each, split at
    ``joints``."""
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeEdge
    from OCP.Geom import Geom_BSplineCurve
    from OCP.gp import gp_Pnt
    from OCP.OCP.collections import Array1_double, Array1_gp_Pnt, Array1_int

    control = np.asarray(spline.control_points, dtype=float)
    knots, mults = np.unique(np.asarray(spline.knots, dtype=float), return_counts=True)
    poles = Array1_gp_Pnt(1, len(control))
    for i, (x, y) in enumerate(control):
        poles.SetValue(i + 1, gp_Pnt(float(x), float(y), 0.0))
    k_arr, m_arr = Array1_double(1, len(knots)), Array1_int(1, len(knots))
    for i, (k, m) in enumerate(zip(knots, mults)):
        k_arr.SetValue(i + 1, float(k))
        m_arr.SetValue(i + 1, int(m))
    curve = Geom_BSplineCurve(poles, k_arr, m_arr, spline.degree)
    cuts = [0]
    joint_index = {int(np.argmin(np.abs(knots - j))) for j in joints}
    for i in range(1, len(knots) - 1):
        if i in joint_index or i - cuts[-1] >= SPANS_PER_EDGE:
            cuts.append(i)
    cuts.append(len(knots) - 1)
    edges = []
    for a, b in itertools.pairwise(cuts):
        piece = Geom_BSplineCurve(curve)            # a copy, cut down to its own spans (and so its own poles)
        piece.Segment(float(knots[a]), float(knots[b]))
        edges.append(BRepBuilderAPI_MakeEdge(piece).Edge())
    return edges


def _face_of_edges(edges):
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace, BRepBuilderAPI_MakeWire

    maker = BRepBuilderAPI_MakeWire()
    for edge in edges:
        maker.Add(edge)
    if not maker.IsDone():
        raise CamcadError("the kernel could not join the outline's edges into a closed wire", "--export step/stl",
                          "report this as a bug with the scene")
    return BRepBuilderAPI_MakeFace(maker.Wire(), True).Face()


def _prism(face, height: float, base: float = 0.0):
    from OCP.BRepBuilderAPI import BRepBuilderAPI_Transform
    from OCP.BRepPrimAPI import BRepPrimAPI_MakePrism
    from OCP.gp import gp_Trsf, gp_Vec

    solid = BRepPrimAPI_MakePrism(face, gp_Vec(0.0, 0.0, float(height))).Shape()
    if base == 0.0:
        return solid
    move = gp_Trsf()
    move.SetTranslation(gp_Vec(0.0, 0.0, float(base)))
    return BRepBuilderAPI_Transform(solid, move, True).Shape()


def _disc(radius: float, height: float, base: float = 0.0):
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeCylinder
    from OCP.gp import gp_Ax2, gp_Dir, gp_Pnt

    return BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(0.0, 0.0, float(base)), gp_Dir(0.0, 0.0, 1.0)), float(radius),
                                    float(height)).Shape()


def _box(x0: float, y0: float, x1: float, y1: float, height: float):
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeBox
    from OCP.gp import gp_Pnt

    return BRepPrimAPI_MakeBox(gp_Pnt(float(x0), float(y0), 0.0), gp_Pnt(float(x1), float(y1), float(height))).Shape()


def _boolean(kind: str, a, b):
    from OCP.BRepAlgoAPI import BRepAlgoAPI_Cut, BRepAlgoAPI_Fuse

    op = BRepAlgoAPI_Cut(a, b) if kind == "cut" else BRepAlgoAPI_Fuse(a, b)
    if not op.IsDone():
        raise CamcadError(f"the kernel's boolean {kind} failed", "--export step/stl", "report this as a bug")
    return op.Shape()


def _min_radius(result: ProfileResult, flank: Flank) -> float:
    theta = np.linspace(0.0, 2.0 * math.pi, 7201)
    return float(np.min(np.hypot(*flank.contour(theta).points.T)))


def part_shape(result: ProfileResult, part: str, thickness: float, bore: float | None = None,
               keyway: tuple[float, float] | None = None, plate: float | None = None,
               groove_depth: float | None = None, tol: float | None = None) -> PartShape:
    """The solid of one part (mm): the cam plate (or the counter-cam's) extruded along +z from z = 0.

    Parameters
    ----------
    result : ProfileResult
        The synthesised cam (not undercut, closed).
    part : str
        "cam" or "counter_cam".
    thickness : float
        Plate thickness, mm.
    bore : float, optional
        Bore diameter, mm; None: no bore.
    keyway : (float, float), optional
        Keyway width W and depth H beyond the bore (mm), on the +y axis; needs a bore.
    plate : float, optional
        Groove cam: the plate's diameter, mm; by default the outer flank's largest diameter plus twice the
        groove's width.
    groove_depth : float, optional
        Groove cam: the groove's depth from the top face, mm (less than the thickness).
    tol : float, optional
        Largest distance between the outline and the exact flank, mm; ``result.settings.tol_mm`` by default.

    Returns
    -------
    PartShape
        The kernel's solid and what went into it.

    Raises
    ------
    CamcadError
        The kernel is missing (what to install), or the bore, keyway or groove do not fit the part.
    """
    kernel()
    tol = result.settings.tol_mm if tol is None else tol
    part_ready(result, "step")
    chosen = [f for f in flanks(result) if f.part == part]
    notes: list[str] = []
    if not (math.isfinite(thickness) and thickness > 0.0):
        raise CamcadError(f"the thickness must be a positive number of mm, got {thickness!r}", "--thickness",
                          "give e.g. --thickness 12")
    inner_radius = min(_min_radius(result, f) for f in chosen[:1])
    worst = 0.0
    outlines = []
    for flank in chosen:
        outline = outline_spline(result, flank.contour, flank.name, tol)
        worst = max(worst, outline.max_deviation)
        outlines.append(_face_of_edges(_edges_of(outline.spline, outline.joints)))
    groove = result.follower.groove and part == "cam"
    if groove:
        if groove_depth is None:
            raise CamcadError("a groove cam's solid needs the groove's depth", "--export step/stl",
                              "give --depth (mm), less than --thickness")
        if not 0.0 < groove_depth < thickness:
            raise CamcadError(f"the groove's depth {groove_depth:g} mm must be less than the thickness "
                              f"{thickness:g} mm", "--depth", "give a depth below the plate's thickness")
        outer = _max_radius(chosen[1])
        width = 2.0 * result.follower.roller_radius
        if plate is None:
            plate = 2.0 * (outer + width)
            notes.append(f"plate diameter {plate:.6g} mm: the outer flank's largest diameter plus twice the "
                         f"groove's width (--plate sets it)")
        elif plate / 2.0 <= outer:
            raise CamcadError(f"a plate of diameter {plate:g} mm does not hold the groove (its outer flank reaches "
                              f"{2.0 * outer:.6g} mm)", "--plate", f"give a diameter above {2.0 * outer:.6g} mm")
        solid = _disc(plate / 2.0, thickness)
        ring = _boolean("cut", _prism(outlines[1], groove_depth, thickness - groove_depth),
                        _prism(outlines[0], groove_depth, thickness - groove_depth))
        solid = _boolean("cut", solid, ring)
    else:
        if plate is not None:
            raise CamcadError("--plate is the plate of a groove cam", "--plate", "drop it for a disc cam")
        solid = _prism(outlines[0], thickness)
    if keyway is not None and bore is None:
        raise CamcadError("a keyway needs a bore", "--keyway", "give --bore D too")
    if bore is not None:
        if not (math.isfinite(bore) and bore > 0.0):
            raise CamcadError(f"the bore must be a positive diameter in mm, got {bore!r}", "--bore",
                              "give e.g. --bore 20")
        reach = bore / 2.0 + (keyway[1] if keyway else 0.0)
        if reach >= inner_radius:
            what = "the bore and its keyway reach" if keyway else "the bore reaches"
            raise CamcadError(f"{what} {reach:.6g} mm from the centre, the profile comes to {inner_radius:.6g} mm",
                              "--bore" if not keyway else "--keyway", "give a smaller bore or keyway")
        hole = _disc(bore / 2.0, thickness)
        if keyway is not None:
            width, depth = keyway
            if not (width > 0.0 and depth > 0.0 and width < bore):
                raise CamcadError(f"keyway {width:g},{depth:g}: the width must be positive and less than the bore, "
                                  "the depth positive", "--keyway", "give W,H in mm, e.g. --keyway 6,2.8")
            hole = _boolean("fuse", hole, _box(-width / 2.0, 0.0, width / 2.0, bore / 2.0 + depth, thickness))
        solid = _boolean("cut", solid, hole)
    else:
        notes.append("no bore (--bore D adds one)")
    return PartShape(part, solid, thickness, bore, keyway, plate, groove_depth if groove else None, worst,
                     tuple(notes))


def _max_radius(flank: Flank) -> float:
    theta = np.linspace(0.0, 2.0 * math.pi, 7201)
    return float(np.max(np.hypot(*flank.contour(theta).points.T)))


def volume(shape) -> float:
    """The kernel's volume of a solid, mm³ (or the file's unit cubed for a shape read from a file)."""
    from OCP.BRepGProp import BRepGProp
    from OCP.GProp import GProp_GProps

    props = GProp_GProps()
    BRepGProp.VolumeProperties_s(shape, props)
    return float(props.Mass())


def step_bytes(shape: PartShape, name: str, units: str = "mm") -> bytes:
    """The STEP file (AP214) of a solid, lengths in mm or inches, with a fixed time stamp and ``name``."""
    from OCP.APIHeaderSection import APIHeaderSection_MakeHeader
    from OCP.IFSelect import IFSelect_RetDone
    from OCP.Interface import Interface_Static
    from OCP.STEPControl import STEPControl_AsIs, STEPControl_Writer
    from OCP.TCollection import TCollection_HAsciiString

    Interface_Static.SetCVal_s("write.step.schema", "AP214IS")
    Interface_Static.SetCVal_s("write.step.unit", "INCH" if units == "in" else "MM")
    Interface_Static.SetCVal_s("write.step.product.name", _ascii(name))
    writer = STEPControl_Writer()
    if writer.Transfer(shape.shape, STEPControl_AsIs) != IFSelect_RetDone:
        raise CamcadError("the kernel could not translate the solid to STEP", "--export step", "report this as a bug")
    header = APIHeaderSection_MakeHeader(writer.Model())
    header.SetName(TCollection_HAsciiString(_ascii(name)))
    header.SetTimeStamp(TCollection_HAsciiString(STEP_TIME_STAMP))
    header.SetAuthorValue(1, TCollection_HAsciiString("camcad"))
    header.SetOrganizationValue(1, TCollection_HAsciiString(""))
    header.SetOriginatingSystem(TCollection_HAsciiString(f"camcad {__version__}"))
    header.SetAuthorisation(TCollection_HAsciiString(""))
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "part.step"
        if writer.Write(str(path)) != IFSelect_RetDone:
            raise CamcadError("the kernel could not write the STEP file", "--export step", "report this as a bug")
        data = path.read_bytes()
    # the kernel's writer stamps the time of the save whatever the header says, and numbers the products it
    # names in a process: the fixed stamp and the design's name instead
    data = re.sub(rb"('[^']*',)'\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d'", rb"\1'" + STEP_TIME_STAMP.encode() + b"'", data,
                  count=1)
    label = _ascii(name).encode("ascii")
    return re.sub(rb"= PRODUCT\('[^']*',\s*'[^']*'", b"= PRODUCT('" + label + b"','" + label + b"'", data, count=1)


def _ascii(text: str) -> str:
    return "".join(ch if 32 <= ord(ch) < 127 and ch != "'" else "_" for ch in text)


def mesh(shape: PartShape, tol: float) -> tuple[np.ndarray, np.ndarray]:
    """The kernel's triangle mesh of a solid within ``tol`` mm: vertices (N, 3) mm, each shared by every face
    that meets there, and triangles (M, 3) of vertex indices, counter-clockwise seen from outside."""
    from OCP.BRep import BRep_Tool
    from OCP.BRepMesh import BRepMesh_IncrementalMesh
    from OCP.TopAbs import TopAbs_FACE, TopAbs_REVERSED
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopLoc import TopLoc_Location
    from OCP.TopoDS import TopoDS

    BRepMesh_IncrementalMesh(shape.shape, float(tol), False, 0.5, False)
    points, triangles = [], []
    offset = 0
    explorer = TopExp_Explorer(shape.shape, TopAbs_FACE)
    while explorer.More():
        face = TopoDS.Face(explorer.Current())
        location = TopLoc_Location()
        tri = BRep_Tool.Triangulation_s(face, location)
        explorer.Next()
        if tri is None:
            continue
        transform = location.Transformation()
        nodes = np.array([[p.X(), p.Y(), p.Z()] for p in
                          (tri.Node(i).Transformed(transform) for i in range(1, tri.NbNodes() + 1))])
        faces = np.array([tri.Triangle(i).Get() for i in range(1, tri.NbTriangles() + 1)], dtype=np.int64) - 1
        if face.Orientation() == TopAbs_REVERSED:
            faces = faces[:, ::-1]
        points.append(nodes)
        triangles.append(faces + offset)
        offset += len(nodes)
    vertices = np.concatenate(points)
    faces = np.concatenate(triangles)
    # a vertex on an edge is computed by each face that meets there: merge those within 1e-9 of the size (each
    # group takes the coordinates of its first vertex, so the same design gives the same file)
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    from scipy.spatial import cKDTree

    scale = max(1.0, float(np.max(np.abs(vertices))))
    pairs = cKDTree(vertices).query_pairs(1e-9 * scale, output_type="ndarray")
    graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(len(vertices),) * 2)
    _, label = connected_components(graph, directed=False)
    _, first, index = np.unique(label, return_index=True, return_inverse=True)
    merged = vertices[first]
    faces = index[faces]
    keep = (faces[:, 0] != faces[:, 1]) & (faces[:, 1] != faces[:, 2]) & (faces[:, 0] != faces[:, 2])
    return merged, faces[keep]


def stl_bytes(vertices: np.ndarray, faces: np.ndarray, name: str, units: str = "mm") -> bytes:
    """A binary STL of the mesh: lengths in mm or inches (said in the 80-byte header), facet normals from the
    vertex order (counter-clockwise seen from outside)."""
    scale = 1.0 / INCH_MM if units == "in" else 1.0
    v = vertices * scale
    a, b, c = v[faces[:, 0]], v[faces[:, 1]], v[faces[:, 2]]
    normal = np.cross(b - a, c - a)
    length = np.linalg.norm(normal, axis=1, keepdims=True)
    normal = np.divide(normal, length, out=np.zeros_like(normal), where=length > 0)
    header = _ascii(f"camcad {name}: units {units}, binary STL")[:80].ljust(80).encode("ascii")
    records = np.zeros(len(faces), dtype=[("n", "<f4", 3), ("a", "<f4", 3), ("b", "<f4", 3), ("c", "<f4", 3),
                                          ("attr", "<u2")])
    records["n"], records["a"], records["b"], records["c"] = normal, a, b, c
    return header + struct.pack("<I", len(faces)) + records.tobytes()

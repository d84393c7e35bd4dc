"""iaa.mesh and iaa.compare against `iaa mesh` and `iaa compare`: the same mesh file and reports,
arrays without copies, the masks, errors with the command's messages."""

import numpy as np
import pytest
from PIL import Image

import iaa
from conftest import assert_same_error, cli_ok, load_json, without_times

FILE_KEYS = ("mesh_file", "mesh_file_coordinates")


@pytest.mark.parametrize("method, flags, kwargs", [
    ("certified", ("--resolution", "32"), {"resolution": 32}),
    ("certified", ("--resolution", "32", "--no-proof-cache"), {"resolution": 32, "proof_cache": False}),
    ("octree", ("--resolution", "32", "--refine", "2"), {"resolution": 32, "refine": 2}),
    ("vtk", ("--grid", "24"), {"grid": 24}),
])
def test_mesh_file_and_report_are_the_commands(teardrop, tmp_path, method, flags, kwargs):
    cli_ok("mesh", teardrop, "--method", method, *flags, "-o", tmp_path / "cli.ply",
           "--report", tmp_path / "r.json", "--threads", "1", "-q")
    m = iaa.mesh(iaa.load_scene(teardrop), method, threads=1, **kwargs)
    m.save(str(tmp_path / "py.ply"))
    assert (tmp_path / "py.ply").read_bytes() == (tmp_path / "cli.ply").read_bytes()
    cli = load_json(tmp_path / "r.json")
    for key in FILE_KEYS:
        cli.pop(key)
    assert without_times(m.report) == without_times(cli)
    assert m.vertices.shape == (cli["vertices"], 3) and m.vertices.dtype == np.float64
    assert m.faces.shape == (cli["triangles"], 3) and m.faces.dtype == np.int32
    assert not m.vertices.flags.owndata and not m.faces.flags.owndata
    assert 0 <= m.faces.min() and m.faces.max() < len(m.vertices)


def test_mesh_vertices_are_the_plys(teardrop, tmp_path):
    m = iaa.mesh(iaa.load_scene(teardrop), resolution=32)
    assert m.report["vertices_duplicated_on_write"] == 0
    m.save(tmp_path / "m.ply")
    with open(tmp_path / "m.ply", "rb") as f:
        header = []
        while not header or header[-1] != "end_header":
            header.append(f.readline().decode().strip())
        rows = [f.readline().split() for _ in range(len(m.vertices))]
        faces = [f.readline().split() for _ in range(len(m.faces))]
    names = [h.split()[-1] for h in header if h.startswith("property double")]
    assert names[:3] == ["x_double", "y_double", "z_double"]
    props = [h.split()[-1] for h in header if h.startswith("property") and "list" not in h]
    at = [props.index(n) for n in names[:3]]
    exact = np.array([[float(r[i]) for i in at] for r in rows])
    assert (exact == m.vertices).all()
    assert (np.array([[int(v) for v in f[1:]] for f in faces]) == m.faces).all()


def test_compare_is_the_commands(teardrop, tmp_path):
    small = ["image.width=64", "image.height=48"]
    scene = iaa.load_scene(teardrop, small)
    m = iaa.mesh(scene, resolution=16)
    m.save(tmp_path / "m.ply")
    sets = [a for s in small for a in ("--set", s)]
    cli_ok("compare", teardrop, "--mesh", tmp_path / "m.ply", "-o", tmp_path / "diff.png",
           "--report", tmp_path / "c.json", *sets, "--threads", "1", "-q")
    c = iaa.compare(scene, m.vertices, m.faces, threads=1)
    cli = load_json(tmp_path / "c.json")
    cli["mesh"] = None
    assert without_times(c.report) == without_times(cli)
    assert (np.asarray(Image.open(tmp_path / "diff.png").convert("RGB")) == c.diff).all()
    assert c.lost.dtype == np.bool_ and c.lost.shape == (48, 64)
    assert int(c.lost.sum()) == cli["lost"] and int(c.wrong.sum()) == cli["wrong"]
    assert (c.lost == (c.agreement == 3)).all() and (c.wrong == (c.agreement == 4)).all()
    assert [[x, y] for y, x in zip(*np.nonzero(c.lost))][:1000] == cli["lost_at"]


def test_a_coarse_mesh_loses_pixels(teardrop):
    scene = iaa.load_scene(teardrop, {"image.width": 100, "image.height": 100})
    m = iaa.mesh(scene, "vtk", grid=8)
    c = iaa.compare(scene, m.vertices, m.faces)
    assert c.lost.any(), "the teardrop's neck should be lost by an 8^3 grid"


@pytest.mark.parametrize("flags, kwargs", [(("--method", "bogus"), {"method": "bogus"}),
                                           (("--resolution", "1"), {"resolution": 1}),
                                           (("--flat-tolerance", "2"), {"flat_tolerance": 2})])
def test_errors_are_the_commands(teardrop, tmp_path, flags, kwargs):
    assert_same_error(("mesh", teardrop, "-o", tmp_path / "m.ply", *flags),
                      lambda: iaa.mesh(iaa.load_scene(teardrop), **kwargs))


def test_bad_arrays(teardrop):
    scene = iaa.load_scene(teardrop, {"image.width": 8, "image.height": 8})
    v = np.zeros((3, 3))
    with pytest.raises(ValueError, match=r"triangle 0 refers to vertex 3 of 3"):
        iaa.compare(scene, v, [[0, 1, 3]])
    with pytest.raises(ValueError, match=r"faces: vertex index -1 out of range"):
        iaa.compare(scene, v, [[0, 1, -1]])
    with pytest.raises(ValueError, match=r"vertices: expected a \(V, 3\) array"):
        iaa.compare(scene, np.zeros((3, 2)), [[0, 1, 2]])
    with pytest.raises(ValueError, match="rays must be in 1..16"):
        iaa.compare(scene, v, [[0, 1, 2]], rays=0)
    with pytest.raises(TypeError):
        iaa.mesh(scene, colour=1)

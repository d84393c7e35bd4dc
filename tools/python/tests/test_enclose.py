"""iaa.enclose against `iaa enclose`: the same leaves (the report's counts, the .vtu's cells) and
report; the guarantee on the boxes; errors with the command's messages."""

import re

import numpy as np
import pytest

import iaa
from conftest import assert_same_error, cli_ok, load_json, without_times


def vtu_cells(path):
    """The number of cells of a VTK XML unstructured grid (the header of its piece)."""
    head = path.read_bytes()[:4096].decode("latin-1")
    return int(re.search(r'NumberOfCells="(\d+)"', head).group(1))


@pytest.mark.parametrize("flags, kwargs", [(("--depth", "5"), {"depth": 5}),
                                           (("--depth", "4", "--refine-possible", "2"),
                                            {"depth": 4, "refine_possible": 2}),
                                           (("--cell-size", "0.05"), {"cell_size": 0.05})])
def test_leaves_and_report_are_the_commands(teardrop, tmp_path, flags, kwargs):
    cli_ok("enclose", teardrop, *flags, "-o", tmp_path / "boxes.vtu", "--report",
           tmp_path / "r.json", "--threads", "1", "-q")
    cli = load_json(tmp_path / "r.json")
    r = iaa.enclose(iaa.load_scene(teardrop), threads=1, **kwargs)
    cli.pop("output")
    assert without_times(r.report) == without_times(cli)
    n = cli["boxes"]
    assert r.boxes.shape == (n, 6) and r.boxes.dtype == np.float64
    assert r.classes.shape == r.depths.shape == (n,) and r.f.shape == (n, 2)
    assert vtu_cells(tmp_path / "boxes.vtu") == n
    assert int((r.classes == 1).sum()) == cli["crossing"]
    assert int((r.classes == 2).sum()) == cli["possible"]
    for level in cli["by_depth"]:
        at = r.depths == level["depth"]
        assert int((r.classes[at] == 1).sum()) == level["crossing"]
        assert int((r.classes[at] == 2).sum()) == level["possible"]


def test_boxes_hold_the_surface(teardrop):
    scene = iaa.load_scene(teardrop)
    r = iaa.enclose(scene, 5)
    assert not r.boxes.flags.owndata
    lo, hi = np.array(scene.bounds)
    x0, x1, y0, y1, z0, z1 = r.boxes.T
    assert (x0 < x1).all() and (y0 < y1).all() and (z0 < z1).all()
    assert (x0 >= lo[0]).all() and (x1 <= hi[0]).all() and (z1 <= hi[2]).all()
    assert ((r.f[:, 0] <= 0) & (0 <= r.f[:, 1])).all()
    # Each kept box may hold surface: 0 lies in f's interval over it (iaa.eval over a row).
    for row in r.boxes[:: max(1, len(r.boxes) // 20)]:
        e = iaa.eval(scene.expression, box=row, params=scene.params)
        assert not e.certified_empty
    # The same leaves for any thread count.
    two = iaa.enclose(scene, 5, threads=2)
    assert (two.boxes == r.boxes).all() and (two.classes == r.classes).all()


@pytest.mark.parametrize("flags, kwargs", [(("--depth", "30"), {"depth": 30}),
                                           (("--refine-possible", "9"), {"refine_possible": 9}),
                                           (("--cell-size", "-1"), {"cell_size": -1}),
                                           (("--depth", "4", "--cell-size", "0.1"),
                                            {"depth": 4, "cell_size": 0.1}),
                                           (("--depth", "6", "--max-boxes", "10"),
                                            {"depth": 6, "max_boxes": 10})])
def test_errors_are_the_commands(teardrop, flags, kwargs):
    assert_same_error(("enclose", teardrop, *flags, "-q"),
                      lambda: iaa.enclose(iaa.load_scene(teardrop), **kwargs))

"""Scenes: loading with overrides, building in Python, and the scene file's checks and messages."""

import pathlib

import pytest

import iaa
from conftest import assert_same_error


def test_load_scene_reads_the_file(teardrop):
    s = iaa.load_scene(teardrop)
    assert s.name == "teardrop"
    assert s.source == teardrop
    assert (s.width, s.height) == (500, 500)
    assert len(s.bounds) == 2 and all(len(c) == 3 for c in s.bounds)
    assert set(s.camera) == {"eye", "look_at", "up", "fov"}
    assert s.settings["method"] == "iaa"
    assert s.lights and "position" in s.lights[0]
    assert "teardrop" in repr(s)


def test_overrides_as_dict_or_as_set_strings(teardrop):
    a = iaa.load_scene(teardrop, {"camera.fov": 30, "image.width": 64, "render.shadows": True})
    b = iaa.load_scene(teardrop, ["camera.fov=30", "image.width=64", "render.shadows=true"])
    assert a.camera["fov"] == b.camera["fov"] == 30
    assert a.width == b.width == 64
    assert a.settings["shadows"] and b.settings["shadows"]
    c = iaa.load_scene(pathlib.Path(teardrop)).with_overrides({"image.height": 32})
    assert c.height == 32 and c.overrides == ["image.height=32"]


@pytest.mark.parametrize("sets", [["camera.fovy=3"], ["camera.fov=0"], ["camera.eye=[-0.05,0,0]"],
                                  ["image.width=0"], ["surface.expression=x^^2"], ["nonsense"]])
def test_errors_are_the_commands(teardrop, sets, tmp_path):
    assert_same_error(("render", teardrop, "-o", tmp_path / "x.png", "--set", sets[0]),
                      lambda: iaa.load_scene(teardrop, sets))
    assert not list(tmp_path.iterdir())


def test_missing_file(tmp_path):
    path = tmp_path / "nope.toml"
    assert_same_error(("render", path, "-o", tmp_path / "x.png"),
                      lambda: iaa.load_scene(str(path)))


SPHERE = "x^2 + y^2 + z^2 - r^2"
TOML = """name = "ball"
[surface]
expression = "x^2 + y^2 + z^2 - r^2"
params = { r = 0.5 }
min = [-1, -1, -1]
max = [1, 1, 1]
[camera]
eye = [0, 0.5, 3]
fov = 35
[image]
width = 40
height = 30
[[light]]
position = [2, 3, 4]
[render]
max_level = 1
"""


def built_ball(**changes):
    args = dict(params={"r": 0.5}, camera={"eye": (0, 0.5, 3), "fov": 35},
                image={"width": 40, "height": 30}, lights=[{"position": [2, 3, 4]}],
                render={"max_level": 1}, name="ball")
    args.update(changes)
    return iaa.Scene(SPHERE, ((-1, -1, -1), (1, 1, 1)), **args)


def test_built_scene_is_the_files(tmp_path):
    path = tmp_path / "ball.toml"
    path.write_text(TOML)
    a, b = iaa.load_scene(str(path)), built_ball()
    for key in ("name", "expression", "params", "bounds", "camera", "width", "height",
                "material", "lights", "settings"):
        assert getattr(a, key) == getattr(b, key), key
    assert (iaa.render(a).image == iaa.render(b).image).all()
    assert b.source == "iaa.Scene"


def test_built_scene_checks_like_a_file():
    with pytest.raises(ValueError) as e:
        built_ball(camera={"fov": 200})
    assert str(e.value) == ("iaa.Scene: key 'camera.fov': must be a finite number in "
                            "[0.001, 179], got 200")
    with pytest.raises(ValueError, match="unknown key 'image.colour'"):
        built_ball(image={"colour": 1})
    with pytest.raises(ValueError, match=r"line 1, column \d+"):
        iaa.Scene("x^^2", ((-1, -1, -1), (1, 1, 1)))
    with pytest.raises(ValueError, match="max must exceed min"):
        iaa.Scene("x", ((1, 1, 1), (1, 2, 2)))
    with pytest.raises(ValueError, match="key 'camera.fov': must be a finite number"):
        built_ball(camera={"fov": float("nan")})
    with pytest.raises(TypeError, match="cannot write a object"):
        built_ball(camera={"fov": object()})

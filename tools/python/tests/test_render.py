"""iaa.render against `iaa render`: the same image, AOV and report bytes; arrays without copies;
errors with the command's messages; threads; progress and cancellation."""

import concurrent.futures
import os
import signal
import threading

import numpy as np
import pytest
from PIL import Image

import iaa
from conftest import assert_same_error, cli_ok, load_json, without_times

SIZE = ("--width", "60", "--height", "40")


def cli_render(scene, tmp_path, *flags):
    out = tmp_path / "cli"
    cli_ok("render", scene, "-o", out / "image.png", *SIZE, "--aov", out / "aov",
           "--report", out / "report.json", "--threads", "1", "-q", *flags)
    return out


@pytest.mark.parametrize("method", [None, "point", "grid 3", "adaptive"])
def test_image_aovs_and_report_are_the_commands(teardrop, tmp_path, method):
    flags = ("--method", method) if method else ()
    out = cli_render(teardrop, tmp_path, *flags)
    r = iaa.render(iaa.load_scene(teardrop), method, 60, 40, threads=1)
    # The image: its pixels are the PNG's, and written with write_png it is the same file.
    assert (np.asarray(Image.open(out / "image.png").convert("RGB")) == r.image).all()
    iaa.write_png(tmp_path / "py.png", r.image)
    assert (tmp_path / "py.png").read_bytes() == (out / "image.png").read_bytes()
    # The AOVs, byte for byte; the certificate image is the certificate array's colours.
    aovs = r.aov_images()
    assert set(aovs) == {"certificate", "coverage", "leaves", "evals"}
    for name, image in aovs.items():
        iaa.write_png(tmp_path / f"{name}.png", image)
        assert (tmp_path / f"{name}.png").read_bytes() == (out / "aov" / f"{name}.png").read_bytes()
    palette = np.array([[235, 235, 235], [30, 150, 60], [235, 110, 20], [128, 128, 128]], np.uint8)
    assert (palette[r.certificate] == aovs["certificate"]).all()
    # The report, but for the wall time.
    assert without_times(r.report) == without_times(load_json(out / "report.json"))


def test_arrays(teardrop):
    r = iaa.render(iaa.load_scene(teardrop), width=60, height=40)
    shapes = {"image": ((40, 60, 3), np.uint8), "linear": ((40, 60, 3), np.float32),
              "certificate": ((40, 60), np.uint8), "coverage": ((40, 60), np.float32),
              "leaves": ((40, 60), np.uint32), "evaluations": ((40, 60), np.uint32)}
    for name, (shape, dtype) in shapes.items():
        a = getattr(r, name)
        assert a.shape == shape and a.dtype == dtype, name
        assert not a.flags.owndata and a.base is not None, f"{name} was copied"
        assert a.flags.c_contiguous
    assert set(np.unique(r.certificate)) <= {0, 1, 2}
    assert ((0 <= r.coverage) & (r.coverage <= 1)).all()
    rep = r.report
    assert rep["pixels"]["rendered"] == 60 * 40
    assert rep["pixels"]["certified_covered"] == int((r.certificate == 1).sum())
    assert rep["pixels"]["uncertain"] == int((r.certificate == 2).sum())
    assert rep["leaves"]["total"] == int(r.leaves.sum())
    # The arrays outlive the result object.
    image = r.image
    del r
    assert image.sum() > 0


def test_window_and_flags(teardrop, tmp_path):
    flags = ("--window", "10,5,50,30", "--max-level", "1", "--threshold", "0.5", "--shadows")
    out = cli_render(teardrop, tmp_path, *flags)
    r = iaa.render(iaa.load_scene(teardrop), width=60, height=40, window=(10, 5, 50, 30),
                   max_level=1, threshold=0.5, shadows=True, threads=1)
    assert (np.asarray(Image.open(out / "image.png").convert("RGB")) == r.image).all()
    assert (r.certificate[:5] == 3).all()  # outside the window: not rendered
    assert without_times(r.report) == without_times(load_json(out / "report.json"))


@pytest.mark.parametrize("flags, kwargs", [
    (("--method", "bogus"), {"method": "bogus"}),
    (("--method", "grid 99"), {"method": "grid 99"}),
    (("--width", "0"), {"width": 0}),
    (("--max-level", "9"), {"max_level": 9}),
    # Negative values are refused by both, not taken for "not given".
    (("--max-level", "-1"), {"max_level": -1}),
    (("--threshold", "-0.5"), {"threshold": -0.5}),
    (("--depth-tol", "-1"), {"depth_tol": -1}),
    (("--adaptive-threshold", "-0.1"), {"adaptive_threshold": -0.1}),
    (("--height", "-5"), {"height": -5}),
    (("--window", "0,0,900,10"), {"window": (0, 0, 900, 10)}),
    (("--window", "1,2"), {"window": "1,2"}),
])
def test_errors_are_the_commands(teardrop, tmp_path, flags, kwargs):
    assert_same_error(("render", teardrop, "-o", tmp_path / "x.png", *flags),
                      lambda: iaa.render(iaa.load_scene(teardrop), **kwargs))


def test_negative_threads_are_an_error(teardrop):
    scene = iaa.load_scene(teardrop)
    with pytest.raises(ValueError, match=r"threads must be in \[0, 1024\]"):
        iaa.render(scene, threads=-1)


def test_same_bytes_for_any_threads_and_from_many_python_threads(teardrop):
    scene = iaa.load_scene(teardrop, {"image.width": 80, "image.height": 60})
    one = iaa.render(scene, threads=1)
    two = iaa.render(scene, threads=2)
    with concurrent.futures.ThreadPoolExecutor(4) as pool:
        many = list(pool.map(lambda m: iaa.render(scene, m, threads=1),
                             ["iaa", "point", "iaa", "adaptive"]))
    for r in (two, many[0], many[2]):
        for name in ("image", "linear", "certificate", "coverage", "leaves", "evaluations"):
            assert (getattr(r, name) == getattr(one, name)).all(), name
    assert (many[1].image == iaa.render(scene, "point").image).all()


def test_progress_reports_on_the_calling_thread(teardrop):
    calls = []
    caller = threading.get_ident()

    def progress(phase, done, total):
        assert threading.get_ident() == caller
        calls.append((phase, done, total))

    iaa.render(iaa.load_scene(teardrop), width=100, height=80, progress=progress)
    assert calls
    phase, done, total = calls[-1]
    assert phase == "render" and done == total > 0


def endless(chubs):
    """A render that would take many minutes (chubs at 2000x2000, max_level 6, one thread): if
    cancelling failed, the test would hang until ctest's timeout."""
    return iaa.load_scene(chubs, {"image.width": 2000, "image.height": 2000,
                                  "render.max_level": 6})


def unfinished(state):
    done, total = state
    return total == 0 or done < total  # not started (the set-up before the first block), or midway


def test_progress_callback_cancels(chubs):
    seen = []

    def progress(phase, done, total):
        seen.append((done, total))
        if len(seen) == 3:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        iaa.render(endless(chubs), threads=1, progress=progress)
    assert len(seen) == 3 and unfinished(seen[-1])
    # Nothing is left behind: the next call works.
    assert iaa.render(iaa.load_scene(chubs), width=20, height=20).image.shape == (20, 20, 3)


def test_ctrl_c_cancels(chubs):
    state = []

    def progress(phase, done, total):
        state[:] = [done, total]

    timer = threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            iaa.render(endless(chubs), threads=1, progress=progress)
    finally:
        timer.cancel()
    assert state and unfinished(state)

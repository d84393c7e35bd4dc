"""iaa: implicit surfaces f(x, y, z) = 0 you can trust, from Python.

Guaranteed rendering, enclosure, meshing and comparison with outward-rounded interval arithmetic,
as the ``iaa`` command runs them, with NumPy arrays for results (docs/python.md)::

    import iaa
    scene = iaa.load_scene("data/scenes/teardrop.toml")
    r = iaa.render(scene, width=200, height=200)
    r.image          # (200, 200, 3) uint8, the pixels of `iaa render`'s PNG
    r.certificate    # (200, 200) uint8: 0 certified empty, 1 certified covered, 2 uncertain
    boxes = iaa.enclose(scene, depth=6).boxes    # (N, 6): x0, x1, y0, y1, z0, z1
    m = iaa.mesh(scene, resolution=64)           # m.vertices (V, 3), m.faces (F, 3)

Bad input raises ValueError with the command's message; Ctrl-C cancels a long call.
"""

from iaa._iaa import (
    CompareResult,
    EncloseResult,
    EvalResult,
    MeshResult,
    RenderResult,
    Scene,
    __version__,
    compare,
    enclose,
    eval,
    load_scene,
    mesh,
    render,
    write_png,
)

# iaa.eval is left out of `from iaa import *`, which would hide Python's own eval.
__all__ = [
    "CompareResult",
    "EncloseResult",
    "EvalResult",
    "MeshResult",
    "RenderResult",
    "Scene",
    "compare",
    "enclose",
    "load_scene",
    "mesh",
    "render",
    "write_png",
]

# Shown as iaa.Scene, iaa.render, ... rather than by the compiled module's name.
for _name in __all__ + ["eval"]:
    globals()[_name].__module__ = "iaa"
del _name

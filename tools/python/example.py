"""The notebook example of docs/python.md and the README, as a script: render the teardrop, show
the image beside the certificate, enclose and mesh it to NumPy, and save the figure.

    PYTHONPATH=build/python /usr/bin/python3 tools/python/example.py docs/img/python-teardrop.png
"""
import sys

import matplotlib

matplotlib.use("Agg")  # no window: the figure goes to a file (drop this line in a notebook)
import matplotlib.pyplot as plt
import numpy as np

import iaa

scene = iaa.load_scene("data/scenes/teardrop.toml")
r = iaa.render(scene, width=300, height=300)
print(r.report["pixels"])  # certified_empty, certified_covered, uncertain, rendered

# The enclosure: boxes (N, 6) that provably hold every point of the surface, and the mesh.
enc = iaa.enclose(scene, depth=6)
crossing = enc.boxes[enc.classes == 1]
m = iaa.mesh(scene, resolution=64)
print(len(crossing), "crossing boxes;", len(m.vertices), "vertices,", len(m.faces), "triangles")

fig = plt.figure(figsize=(12, 4.2))
ax = fig.add_subplot(1, 3, 1)
ax.imshow(r.image)
ax.set_title("iaa.render: image")
ax = fig.add_subplot(1, 3, 2)
states = matplotlib.colors.ListedColormap(["#ebebeb", "#1e963c", "#eb6e14"])
ax.imshow(r.certificate, cmap=states, vmin=0, vmax=2, interpolation="nearest")
ax.set_title("certificate: empty, covered, uncertain")
ax = fig.add_subplot(1, 3, 3, projection="3d")
x, y, z = m.vertices.T
ax.plot_trisurf(x, y, z, triangles=m.faces, color="#d98c4d", linewidth=0, alpha=0.6)
centres = np.column_stack([crossing[:, 0:2].mean(1), crossing[:, 2:4].mean(1),
                           crossing[:, 4:6].mean(1)])
ax.scatter(*centres[::4].T, s=0.3, c="#1e6432", alpha=0.5)
ax.set_title("iaa.mesh, and iaa.enclose's crossing boxes")
ax.view_init(elev=20, azim=-60)
for a in fig.axes[:2]:
    a.set_axis_off()
fig.subplots_adjust(left=0.01, right=0.99, top=0.9, bottom=0.03, wspace=0.05)
fig.savefig(sys.argv[1] if len(sys.argv) > 1 else "teardrop.png", dpi=80)

#!/usr/bin/python3
"""Draws a uascma city map: building footprints shaded by height, landing sites coloured by risk.

Usage: city_map.py MAP.json OUT.png
MAP.json is written by `uascma map info --plot OUT.png`: {"title", "buildings": [{"rings", "height"}],
"sites": [{"x", "y", "risk", "radius", "rooftop"}]}, positions in metres in the local frame (x north, y east).
The plot puts east to the right and north up. A building's rings follow the even-odd rule (outer rings, holes,
further parts), drawn so that holes stay open.
"""
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.collections import PatchCollection  # noqa: E402
from matplotlib.patches import PathPatch  # noqa: E402
from matplotlib.path import Path  # noqa: E402


def signed_area(ring):
    return 0.5 * sum(a[0] * b[1] - b[0] * a[1] for a, b in zip(ring, ring[1:] + ring[:1]))


def building_path(rings):
    """One compound path; each ring oriented by how many other rings contain it (even: outer, odd: hole), so
    matplotlib's non-zero fill leaves the holes open."""
    rings = [[(p[1], p[0]) for p in ring] for ring in rings]  # (east, north) for the plot
    paths = [Path(ring + [ring[0]], closed=True) for ring in rings]
    vertices, codes = [], []
    for k, ring in enumerate(rings):
        depth = sum(1 for j, other in enumerate(paths) if j != k and other.contains_point(ring[0]))
        counter_clockwise = signed_area(ring) > 0
        if counter_clockwise != (depth % 2 == 0):
            ring = ring[::-1]
        vertices += ring + [ring[0]]
        codes += [Path.MOVETO] + [Path.LINETO] * (len(ring) - 1) + [Path.CLOSEPOLY]
    return Path(vertices, codes)


def main(source, target):
    with open(source) as f:
        data = json.load(f)
    buildings = data["buildings"]
    sites = data["sites"]
    fig, ax = plt.subplots(figsize=(10, 9))
    if buildings:
        heights = [b["height"] for b in buildings]
        patches = [PathPatch(building_path(b["rings"])) for b in buildings]
        collection = PatchCollection(patches, cmap="Greys", edgecolor="#555555", linewidth=0.3)
        collection.set_array(heights)
        collection.set_clim(0, max(heights))
        ax.add_collection(collection)
        fig.colorbar(collection, ax=ax, shrink=0.6, label="building height (m)")
    if sites:
        scatter = ax.scatter([s["y"] for s in sites], [s["x"] for s in sites], c=[s["risk"] for s in sites],
                             cmap="RdYlGn_r", vmin=0.0, vmax=1.0, s=[max(6.0, 2.0 * s["radius"]) for s in sites],
                             marker="o", edgecolors="black", linewidths=0.2, zorder=3)
        fig.colorbar(scatter, ax=ax, shrink=0.6, label="landing-site risk")
    ax.autoscale_view()
    ax.set_aspect("equal")
    ax.set_xlabel("east y (m)")
    ax.set_ylabel("north x (m)")
    ax.set_title(data.get("title", "city map"), fontsize=10)
    fig.tight_layout()
    fig.savefig(target, dpi=120)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])

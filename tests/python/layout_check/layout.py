"""The layout check of tests/python/test_plots.py: a figure's problems, found with matplotlib's own extents
(Artist.get_window_extent under the figure's renderer):

* two texts overlap (titles, axis labels, tick labels, annotations, legend entries): their boxes intersect by
  more than MIN_OVERLAP_PX in both directions;
* a legend covers data: a point of a line or a scatter of its axes lies inside the legend's box;
* a label placed in an axes (ax.text, ax.annotate) sits on its data: a marker, an error bar or a bar;
* a text is too small to read: under MIN_TEXT_PX pixels high at the figure's dpi (the size drawn: a table
  cell's text shrunk to fit is measured as drawn);
* a text or a legend is cut at the figure's edge: its box reaches more than MIN_OVERLAP_PX outside the figure
  (not checked for a figure saved with bbox_inches="tight", whose saved frame grows to hold it).
"""
MIN_OVERLAP_PX = 1.0   # ours: touching boxes (shared edges, rounding) are not an overlap
MIN_TEXT_PX = 8.0      # ours: 6 pt at 96 dpi; smaller glyphs are not legible on a screen


def _texts(fig):
    import matplotlib.text

    out = []
    for text in fig.findobj(matplotlib.text.Text):
        if not text.get_visible() or not text.get_text().strip():
            continue
        # Tick labels matplotlib keeps but does not draw (outside the view) have no place on the figure.
        axes = text.axes
        if axes is not None and getattr(text, "get_clip_on", lambda: False)() and not text.get_in_layout():
            continue
        out.append(text)
    return out


def _visible_tick_labels(fig):
    labels = set()
    for axes in fig.axes:
        for axis in (axes.xaxis, axes.yaxis) + ((axes.zaxis,) if hasattr(axes, "zaxis") else ()):
            lo, hi = sorted(axis.get_view_interval())
            for tick in axis.get_major_ticks() + axis.get_minor_ticks():
                loc = tick.get_loc()
                # axis("off"): matplotlib keeps the tick labels but draws none of them.
                if not axes.axison or loc is None or not (lo - 1e-9 * abs(hi - lo) <= loc <= hi + 1e-9 * abs(hi - lo)):
                    labels.add(id(tick.label1))
                    labels.add(id(tick.label2))
    return labels  # ids of tick labels outside the view: not drawn


def _cut_at_edge(fig, box):
    """How far (px) `box` reaches outside the figure, the largest of its four sides."""
    return max(-box.x0, box.x1 - fig.bbox.width, -box.y0, box.y1 - fig.bbox.height)


def _legends(fig):
    out = [legend for legend in getattr(fig, "legends", []) if legend.get_visible()]
    for axes in fig.axes:
        legend = axes.get_legend()
        if legend is not None and legend.get_visible():
            out.append(legend)
    return out


def check(fig, tight=False):
    """The figure's problems; tight: it is saved with bbox_inches="tight" (its edge cuts nothing)."""
    import numpy as np

    problems = []
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    hidden = _visible_tick_labels(fig)
    texts = [t for t in _texts(fig) if id(t) not in hidden]
    boxes = []
    for text in texts:
        box = text.get_window_extent(renderer)
        if box.width <= 0 or box.height <= 0:
            continue
        boxes.append((text, box))
        size_px = text.get_fontsize() * fig.dpi / 72.0
        if size_px < MIN_TEXT_PX:
            problems.append(f"text {text.get_text()!r} is {size_px:.1f} px high (< {MIN_TEXT_PX})")
        cut = _cut_at_edge(fig, box)
        if not tight and cut > MIN_OVERLAP_PX:
            problems.append(f"text {text.get_text()!r} is cut at the figure's edge ({cut:.0f} px outside)")
    for legend in _legends(fig):
        cut = _cut_at_edge(fig, legend.get_window_extent(renderer))
        if not tight and cut > MIN_OVERLAP_PX:
            problems.append(f"a legend is cut at the figure's edge ({cut:.0f} px outside)")
    for i in range(len(boxes)):
        for j in range(i + 1, len(boxes)):
            (a, ba), (b, bb) = boxes[i], boxes[j]
            dx = min(ba.x1, bb.x1) - max(ba.x0, bb.x0)
            dy = min(ba.y1, bb.y1) - max(ba.y0, bb.y0)
            if dx > MIN_OVERLAP_PX and dy > MIN_OVERLAP_PX:
                problems.append(f"texts overlap: {a.get_text()!r} and {b.get_text()!r} ({dx:.0f} x {dy:.0f} px)")
    # Labels placed in an axes (ax.text, ax.annotate) must not sit on its data: a line's points (error-bar caps
    # included) or a bar.
    for axes in fig.axes:
        if hasattr(axes, "zaxis"):
            continue
        bars = [p.get_window_extent(renderer) for p in axes.patches if p.get_visible()]
        points = []
        for line in axes.get_lines():
            xy = np.asarray(line.get_xydata(), dtype=float)
            if line.get_visible() and len(xy):
                if line.get_linestyle() not in ("None", "", " ") and line.get_marker() in (None, "None", "", " "):
                    continue  # a line without markers: its vertices alone do not show where it runs
                points.append(line.get_transform().transform(xy))
        for collection in axes.collections:  # error bars: points along each segment, 1 % of it apart
            for segment in getattr(collection, "get_segments", lambda: [])():
                segment = np.asarray(segment, dtype=float)
                if len(segment) >= 2 and collection.get_visible():
                    along = np.linspace(0.0, 1.0, 101)[:, None]
                    points.append(collection.get_transform().transform(
                        np.concatenate([a + along * (b - a) for a, b in zip(segment[:-1], segment[1:])])))
        points = np.concatenate(points) if points else np.zeros((0, 2))
        for text in axes.texts:
            if not text.get_visible() or not text.get_text().strip():
                continue
            box = text.get_window_extent(renderer)
            inside = np.sum((points[:, 0] > box.x0) & (points[:, 0] < box.x1) & (points[:, 1] > box.y0) &
                            (points[:, 1] < box.y1)) if len(points) else 0
            # A label wholly inside one patch is that patch's own label (a cell of a table drawn as patches).
            inside_one = any(b.x0 <= box.x0 and box.x1 <= b.x1 and b.y0 <= box.y0 and box.y1 <= b.y1 for b in bars)
            on_bars = 0 if inside_one else sum(
                1 for b in bars if min(b.x1, box.x1) - max(b.x0, box.x0) > MIN_OVERLAP_PX and
                min(b.y1, box.y1) - max(b.y0, box.y0) > MIN_OVERLAP_PX)
            if inside or on_bars:
                problems.append(f"label {text.get_text()!r} sits on data ({inside} points, {on_bars} bars)")
    for axes in fig.axes:
        legend = axes.get_legend()
        if legend is None or not legend.get_visible() or hasattr(axes, "zaxis"):
            continue
        box = legend.get_window_extent(renderer)
        covered = 0
        for line in axes.get_lines():
            if not line.get_visible() or line.get_label().startswith("_child") and False:
                continue
            xy = line.get_xydata()
            if len(xy) == 0:
                continue
            points = line.get_transform().transform(np.asarray(xy, dtype=float))
            points = points[np.all(np.isfinite(points), axis=1)]
            covered += int(np.sum((points[:, 0] > box.x0) & (points[:, 0] < box.x1) &
                                  (points[:, 1] > box.y0) & (points[:, 1] < box.y1)))
        for collection in axes.collections:
            offsets = collection.get_offsets()
            if len(offsets) == 0 or not collection.get_visible():
                continue
            points = collection.get_offset_transform().transform(np.asarray(offsets, dtype=float))
            covered += int(np.sum((points[:, 0] > box.x0) & (points[:, 0] < box.x1) &
                                  (points[:, 1] > box.y0) & (points[:, 1] < box.y1)))
        if covered:
            problems.append(f"the legend of axes {axes.get_title()!r} covers {covered} data points")
    return problems



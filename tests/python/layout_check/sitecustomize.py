"""Loaded by every Python interpreter started with this folder on PYTHONPATH (tests/python/test_plots.py): wraps
matplotlib's Figure.savefig so that each figure a plotting script writes is checked (layout.check) before it is
saved, and the problems appended as one JSON line per figure to $UASCMA_LAYOUT_REPORT. (It shadows Debian's own
sitecustomize, which only matters for crash reports, in those interpreters alone.)
"""
import json
import os


def _install():
    report = os.environ.get("UASCMA_LAYOUT_REPORT")
    if not report:
        return
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.figure import Figure

    original = Figure.savefig

    def savefig(self, fname, *args, **kwargs):
        if "dpi" in kwargs and kwargs["dpi"] not in (None, "figure"):
            self.set_dpi(kwargs["dpi"])
        from layout import check

        problems = check(self, tight=kwargs.get("bbox_inches") == "tight")
        with open(report, "a") as f:
            f.write(json.dumps({"file": os.path.basename(os.fspath(fname)), "problems": problems}) + "\n")
        return original(self, fname, *args, **kwargs)

    Figure.savefig = savefig


_install()

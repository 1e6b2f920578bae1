#!/usr/bin/python3
"""A real browser reads `uascma reproduce`'s page: headless Chromium (Debian's `chromium`) loads
DIR/index.html, and the DOM it renders must hold, for every item of DIR/results.json, its section, its verdict
(the same as results.json's) and every figure as a decoded PNG image.

Usage: reproduce_browser_test.py UASCMA CHROMIUM [reproduce options...]
       reproduce_browser_test.py UASCMA CHROMIUM --dir=DIR     (check the page of a run already made in DIR)
  e.g. reproduce_browser_test.py build/uascma /usr/bin/chromium --only table-2.2,cma-policy,scenario-1
       reproduce_browser_test.py build/uascma /usr/bin/chromium --quick        (every item)
CHROMIUM is a path or a name looked up on the PATH. Exit 0 when every check holds, 1 otherwise (each failure
printed), 77 when CHROMIUM is not installed.
"""
import base64
import html.parser
import json
import shutil
import subprocess
import sys
import tempfile


class Dom(html.parser.HTMLParser):
    """Sections by id, the verdict spans and figures (with their <img> sources) inside each."""

    def __init__(self):
        super().__init__()
        self.sections = {}
        self.current = None
        self.verdict_open = False
        self.figure = None

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag == "section" and a.get("id", "").startswith("item-"):
            self.current = {"verdict": None, "figures": {}, "h2": False}
            self.sections[a["id"][len("item-"):]] = self.current
        elif self.current is not None and tag == "span" and "data-verdict" in a:
            self.current["verdict"] = a["data-verdict"]
        elif self.current is not None and tag == "figure":
            self.figure = a.get("data-figure")
            self.current["figures"][self.figure] = None
        elif self.current is not None and tag == "img" and self.figure is not None:
            self.current["figures"][self.figure] = a.get("src", "")
        elif self.current is not None and tag == "h2":
            self.current["h2"] = True

    def handle_endtag(self, tag):
        if tag == "section":
            self.current = None
        elif tag == "figure":
            self.figure = None


# CTest's SKIP_RETURN_CODE for this test (tests/CMakeLists.txt): the browser is not installed.
SKIPPED = 77


def main():
    uascma, chromium, options = sys.argv[1], sys.argv[2], sys.argv[3:]
    if shutil.which(chromium) is None:
        print(f"reproduce_browser: skipped: {chromium} is not on the PATH (scripts/install-deps.sh test-tools)")
        sys.exit(SKIPPED)
    failures = []
    existing = options[0][len("--dir="):] if options and options[0].startswith("--dir=") else None
    with tempfile.TemporaryDirectory() as scratch:
        out = existing or scratch
        if existing is None:
            run = subprocess.run([uascma, "reproduce", "--out", out] + options, capture_output=True, text=True)
            if run.returncode != 0:
                print(run.stdout, run.stderr)
                sys.exit(f"uascma reproduce exited {run.returncode}")
        results = json.load(open(f"{out}/results.json"))
        dom_text = subprocess.run(
            [chromium, "--headless", "--no-sandbox", "--disable-gpu", "--user-data-dir=" + scratch + "/profile",
             "--dump-dom", f"file://{out}/index.html"],
            capture_output=True, text=True, timeout=120).stdout
        if "<section" not in dom_text:
            sys.exit("chromium rendered no sections (is it installed? scripts/install-deps.sh test-tools)")
        dom = Dom()
        dom.feed(dom_text)
        for item in results["items"]:
            section = dom.sections.get(item["id"])
            if section is None:
                failures.append(f"{item['id']}: no section in the rendered page")
                continue
            if not section["h2"]:
                failures.append(f"{item['id']}: the section has no heading")
            if section["verdict"] != item["verdict"]:
                failures.append(f"{item['id']}: verdict {section['verdict']!r} on the page, {item['verdict']!r} in results.json")
            for figure in item["figures"]:
                src = section["figures"].get(figure["file"])
                prefix = "data:image/png;base64,"
                if not src or not src.startswith(prefix):
                    failures.append(f"{item['id']}: figure {figure['file']} is not an embedded PNG")
                elif not base64.b64decode(src[len(prefix):]).startswith(b"\x89PNG\r\n\x1a\n"):
                    failures.append(f"{item['id']}: figure {figure['file']} does not decode to a PNG")
        checked = len(results["items"])
    for f in failures:
        print("FAIL:", f)
    print(f"{checked} items checked in the DOM chromium rendered, {len(failures)} failures")
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()

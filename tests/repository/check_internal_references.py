#!/usr/bin/env python3
"""Fails when the text a user gets names a document the user does not have.

The product cites the dissertation, docs/modelling-choices.md, docs/defaults.md and its own files. This check scans
every text file under the folders a user reads (src, include, apps, python, tests, examples, docs) and README.md and
CONTRIBUTING.md for the patterns of tests/repository/internal-references.txt: ticket and decision numbers, work
sessions and rounds, paths to a folder beside the repository. A reference split over two lines ("decisions" at the
end of one comment line, "item 7" at the start of the next) is found too. Before scanning, the check runs its own
examples (the file's "flag" and "pass" lines), so a pattern that stops matching fails the test.

    python3 tests/repository/check_internal_references.py [--root DIR]

Exit status 0 when nothing is found, 1 with one line per finding (file:line: what, the text), 2 on a bad pattern file.
"""
import argparse
import os
import re
import sys

SCANNED = ["src", "include", "apps", "python", "tests", "examples", "docs", "README.md", "CONTRIBUTING.md"]
PATTERN_FILE = os.path.join("tests", "repository", "internal-references.txt")
SKIPPED_DIRS = {"__pycache__", ".git", ".pytest_cache"}
# Comment markers and string quotes stripped where two lines are joined: "// decisions" + "// item 7".
CONTINUATION = re.compile(r'^\s*(//+|#+|\*+|"|\')?\s*')


def load_patterns(path):
    patterns, flags, passes = [], [], []
    with open(path, encoding="utf-8") as f:
        for number, line in enumerate(f, 1):
            line = line.rstrip("\n")
            if not line or line.startswith("#"):
                continue
            kind, _, rest = line.partition("\t")
            if kind == "pattern":
                regex, _, meaning = rest.partition("\t")
                patterns.append((re.compile(regex, re.IGNORECASE), meaning or regex))
            elif kind == "flag":
                flags.append(rest)
            elif kind == "pass":
                passes.append(rest)
            else:
                sys.exit(f"{path}:{number}: expected 'pattern', 'flag' or 'pass' and a tab, got {line!r}")
    if not patterns or not flags or not passes:
        sys.exit(f"{path}: expected at least one pattern, one flag example and one pass example")
    return patterns, flags, passes


def first_match(patterns, text):
    for regex, meaning in patterns:
        if regex.search(text):
            return meaning
    return None


def self_check(patterns, flags, passes):
    wrong = [f"not flagged: {t!r}" for t in flags if first_match(patterns, t) is None]
    wrong += [f"flagged: {t!r} ({first_match(patterns, t)})" for t in passes if first_match(patterns, t)]
    # The two-line join must find a reference split across lines and nothing in two clean lines.
    if not split_findings(patterns, ["// the reach margin (decisions", "// item 7) at 1 Hz"]):
        wrong.append("a decision item split over two comment lines was not found")
    if split_findings(patterns, ["// a sample sd of 0.1 around", "// 0.1 at seed 1"]):
        wrong.append("two clean lines were flagged when joined")
    return wrong


def split_findings(patterns, lines):
    found = []
    for i in range(len(lines) - 1):
        first, second = lines[i].rstrip().rstrip("\"'"), CONTINUATION.sub("", lines[i + 1], count=1)
        joined = first + " " + second
        meaning = first_match(patterns, joined)
        if meaning and not first_match(patterns, lines[i]) and not first_match(patterns, lines[i + 1]):
            found.append((i + 1, meaning, joined.strip()))
    return found


def text_files(root):
    for entry in SCANNED:
        path = os.path.join(root, entry)
        if os.path.isfile(path):
            yield entry
        for directory, dirs, files in os.walk(path):
            dirs[:] = sorted(d for d in dirs if d not in SKIPPED_DIRS)
            for name in sorted(files):
                yield os.path.relpath(os.path.join(directory, name), root)


def scan(root, patterns):
    findings = []
    for relative in text_files(root):
        if os.path.normpath(relative) == os.path.normpath(PATTERN_FILE):
            continue
        try:
            with open(os.path.join(root, relative), encoding="utf-8") as f:
                lines = f.read().split("\n")
        except (UnicodeDecodeError, OSError):
            continue  # images and other binary files carry no citations
        for number, line in enumerate(lines, 1):
            meaning = first_match(patterns, line)
            if meaning:
                findings.append(f"{relative}:{number}: {meaning}: {line.strip()[:160]}")
        for number, meaning, joined in split_findings(patterns, lines):
            findings.append(f"{relative}:{number}: {meaning} (over two lines): {joined[:160]}")
    return findings


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--root", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
    root = os.path.abspath(parser.parse_args().root)
    patterns, flags, passes = load_patterns(os.path.join(root, PATTERN_FILE))
    wrong = self_check(patterns, flags, passes)
    if wrong:
        print("the check's own examples fail:\n  " + "\n  ".join(wrong))
        return 2
    findings = scan(root, patterns)
    for finding in findings:
        print(finding)
    if findings:
        print(f"{len(findings)} lines name a document the user does not have: cite the dissertation, "
              "docs/modelling-choices.md#ANCHOR or docs/defaults.md#ANCHOR instead")
        return 1
    print("no line names an issue, a decision number, a work session or round, or a folder beside the repository")
    return 0


if __name__ == "__main__":
    sys.exit(main())

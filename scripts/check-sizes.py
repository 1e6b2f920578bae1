#!/usr/bin/env python3
"""Size rules for the C++ sources under src/ (ours: no function above 80 lines, no file above 700).

    python3 scripts/check-sizes.py [--root DIR] [--max-function N] [--max-file N] [--list]

- no function longer than --max-function lines (80), counted from the line of its opening brace to the
  line of its closing brace, both included;
- no file longer than --max-file lines (700).

Every offender is printed as `file:line name lines` (the function's opening-brace line, or line 1 for a
file), longest first; the exit status is 1 when there is any, 0 otherwise. --list also prints the
functions that pass, which is how the scanner is checked by hand.

The scanner is C++-aware enough for this tree: comments, string and character literals (raw strings and
digit separators included) and preprocessor lines are blanked before braces are counted, so a brace inside
them counts for nothing. A brace at namespace or class scope opens a function body when the text before it
(since the previous `;`, `{` or `}`) holds a parameter list; everything nested inside a function (blocks,
lambdas, local classes) belongs to the enclosing function. Member-initialiser braces (`x_{a}` after
`Foo() :`) are recognised and skipped; namespaces, classes, structs, unions, enums and `extern "C"` blocks
are scopes whose own braces are not counted. A namespace-scope variable initialised with a lambda
(`const auto f = [](...) {`) counts as a function named after the variable; any other initialiser
(`= {...}`, `kTable{...}`) is data and is not measured.
"""
import argparse
import os
import re
import sys

SOURCE_SUFFIXES = (".cc", ".cpp", ".cxx", ".h", ".hpp")
SCOPE_KEYWORDS = {"namespace", "class", "struct", "union", "enum", "extern"}


def blank_literals(text):
    """Returns text with comments, string/char literals and preprocessor lines replaced by spaces.

    Newlines are kept, so line numbers do not move."""
    out = []
    i, n = 0, len(text)
    line_start = True  # only whitespace since the last newline
    while i < n:
        c = text[i]
        if c == "\n":
            out.append(c)
            i += 1
            line_start = True
            continue
        if line_start and c == "#":  # preprocessor line, with its continuations
            while i < n and text[i] != "\n":
                if text[i] == "\\" and i + 1 < n and text[i + 1] == "\n":
                    out.append(" \n")
                    i += 2
                    continue
                out.append(" ")
                i += 1
            continue
        if not c.isspace():
            line_start = False
        if text.startswith("//", i):
            while i < n and text[i] != "\n":
                out.append(" ")
                i += 1
            continue
        if text.startswith("/*", i):
            end = text.find("*/", i + 2)
            end = n if end < 0 else end + 2
            out.append(re.sub(r"[^\n]", " ", text[i:end]))
            i = end
            continue
        if c == '"':
            # Raw string: R"delim( ... )delim", possibly with an encoding prefix (u8R, LR, ...).
            j = i - 1
            if j >= 0 and text[j] == "R" and (j == 0 or not (text[j - 1].isalnum() or text[j - 1] == "_")
                                               or text[j - 1] in "uL8"):
                paren = text.find("(", i + 1)
                delim = text[i + 1:paren]
                end = text.find(")" + delim + '"', paren + 1)
                end = n if end < 0 else end + len(delim) + 2
                out.append('"' + re.sub(r"[^\n]", " ", text[i + 1:end - 1]) + '"')
                i = end
                continue
            j = i + 1
            while j < n and text[j] != '"':
                j += 2 if text[j] == "\\" else 1
            out.append('"' + re.sub(r"[^\n]", " ", text[i + 1:j]) + '"')
            i = j + 1
            continue
        if c == "'":
            # A digit separator (1'000) when the token it sits in starts with a digit.
            k = i - 1
            while k >= 0 and (text[k].isalnum() or text[k] in "_."):
                k -= 1
            if k + 1 < i and text[k + 1].isdigit():
                out.append(c)
                i += 1
                continue
            j = i + 1
            while j < n and text[j] != "'":
                j += 2 if text[j] == "\\" else 1
            out.append("'" + re.sub(r"[^\n]", " ", text[i + 1:j]) + "'")
            i = j + 1
            continue
        out.append(c)
        i += 1
    return "".join(out)


def strip_template_prefix(header):
    """Drops leading `template <...>` clauses (nested angle brackets included)."""
    h = header.lstrip()
    while h.startswith("template"):
        k = h.find("<")
        if k < 0:
            break
        depth, j = 0, k
        while j < len(h):
            if h[j] == "<":
                depth += 1
            elif h[j] == ">":
                depth -= 1
                if depth == 0:
                    break
            j += 1
        h = h[j + 1:].lstrip()
    return h


def top_level(header, char):
    """Index of the first `char` outside (), [], {} and <> in header, or -1."""
    depth = 0
    for k, c in enumerate(header):
        if c == char and depth == 0:
            return k
        if c in "([{":
            depth += 1
        elif c in ")]}":
            depth -= 1
    return -1


def function_name(header):
    """The declarator's name: the qualified identifier before the parameter list."""
    h = re.sub(r"\s+", " ", header)
    m = re.search(r"([~\w:]*operator\s*(?:\(\)|\[\]|<=>|[^\w\s(]+|\s\w[\w:]*))\s*\(", h)
    if m:
        return m.group(1).replace(" ", "")
    while True:  # drop template arguments, innermost first: std::function<void()> Make() names Make
        stripped = re.sub(r"<[^<>]*>", "", h)
        if stripped == h:
            break
        h = stripped
    k = top_level(h, "(")
    m = re.search(r"[~\w:]+$", h[:k].rstrip()) if k >= 0 else None
    return m.group(0) if m else "?"


def classify(header):
    """What a `{` at namespace/class scope opens: 'scope', 'function', 'init' or 'data'."""
    h = strip_template_prefix(header)
    h = re.sub(r"^(\[\[[^\]]*\]\]\s*)+", "", h)
    words = re.findall(r"[A-Za-z_]\w*", h[:80])
    first = words[0] if words else ""
    if first in ("inline", "export") and len(words) > 1:
        first = words[1]
    if first == "typedef" and len(words) > 1:
        first = words[1]
    if first in SCOPE_KEYWORDS and top_level(h, "(") < 0:
        return "scope"
    if first in ("class", "struct", "union", "enum"):
        return "scope"
    eq = top_level(h, "=")
    # `operator=`, `operator==` ... are declarators, not initialisers.
    if eq >= 0 and not re.search(r"operator\s*$", h[:eq]) and h[eq + 1:eq + 2] != "=":
        rest = h[eq + 1:].lstrip()
        if rest.startswith("[") and "(" in rest or rest.startswith("[]"):
            return "lambda"
        return "data"
    if top_level(h, "(") < 0:
        return "data"
    # After `) :` (a constructor's member initialisers) a brace right after a name or `>` initialises a
    # member; the body's brace follows `)` or `}` (or a specifier such as noexcept).
    close = h.rfind(")")
    if close >= 0 and re.search(r"^\s*(noexcept\s*)?:(?!:)", h[close + 1:]):
        tail = h.rstrip()
        if tail and (tail[-1].isalnum() or tail[-1] in "_>"):
            last_word = re.search(r"(\w+)$", tail)
            if not last_word or last_word.group(1) not in ("noexcept", "const", "override", "final", "mutable"):
                return "init"
    return "function"


def lambda_name(header):
    h = strip_template_prefix(header)
    eq = top_level(h, "=")
    m = re.search(r"(\w+)\s*$", h[:eq])
    return (m.group(1) if m else "?") + " (lambda)"


def measure_functions(text):
    """[(line, name, lines)] for every function defined in text (already blanked)."""
    found = []
    stack = []  # entries: ('scope' | 'function' | 'data' | 'init', start_line, name)
    header = []
    line = 1
    for c in text:
        if c == "\n":
            line += 1
        in_body = any(kind in ("function", "data") for kind, _, _ in stack)
        if c == "{":
            if in_body:
                stack.append(("inner", line, ""))
                continue
            h = "".join(header)
            kind = classify(h)
            if kind == "init":
                stack.append(("init", line, ""))
                continue  # the header goes on: the body's brace is still to come
            if kind == "lambda":
                stack.append(("function", line, lambda_name(h)))
            elif kind == "function":
                stack.append(("function", line, function_name(h)))
            else:
                stack.append((kind, line, ""))
            header = []
        elif c == "}":
            if not stack:
                continue
            kind, start, name = stack.pop()
            if kind == "function":
                found.append((start, name, line - start + 1))
            if kind != "init" and not in_body_after(stack):
                header = []
            elif kind == "init":
                header.append("}")
        elif c == ";":
            if not in_body:
                header = []
        elif not in_body:
            header.append(c)
    return found


def in_body_after(stack):
    return any(kind in ("function", "data") for kind, _, _ in stack)


def scan(root, max_function, max_file, list_all):
    offenders = []
    passing = []
    src = os.path.join(root, "src")
    for dirpath, _, files in os.walk(src):
        for name in sorted(files):
            if not name.endswith(SOURCE_SUFFIXES):
                continue
            path = os.path.join(dirpath, name)
            rel = os.path.relpath(path, root)
            with open(path, encoding="utf-8") as f:
                text = f.read()
            n_lines = text.count("\n") + (0 if text.endswith("\n") or not text else 1)
            if n_lines > max_file:
                offenders.append((rel, 1, "(file)", n_lines))
            for start, fname, lines in measure_functions(blank_literals(text)):
                entry = (rel, start, fname, lines)
                (offenders if lines > max_function else passing).append(entry)
    offenders.sort(key=lambda e: (-e[3], e[0], e[1]))
    if list_all:
        for rel, start, fname, lines in sorted(passing):
            print(f"ok {rel}:{start} {fname} {lines}")
    for rel, start, fname, lines in offenders:
        print(f"{rel}:{start} {fname} {lines}")
    n_files = sum(1 for e in offenders if e[2] == "(file)")
    print(f"check-sizes: {len(offenders) - n_files} functions above {max_function} lines, "
          f"{n_files} files above {max_file} lines", file=sys.stderr)
    return 1 if offenders else 0


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--root", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
    parser.add_argument("--max-function", type=int, default=80)
    parser.add_argument("--max-file", type=int, default=700)
    parser.add_argument("--list", action="store_true")
    args = parser.parse_args()
    return scan(os.path.abspath(args.root), args.max_function, args.max_file, args.list)


if __name__ == "__main__":
    sys.exit(main())

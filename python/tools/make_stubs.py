#!/usr/bin/python3
"""Writes the type stub of the compiled module, uascma/_uascma.pyi, from the module itself (run by the build
after the module is linked: python/CMakeLists.txt), so the stub always says what the build contains.

Usage: PYTHONPATH=build/python make_stubs.py OUT.pyi

Every function, method and property of uascma._uascma is written from pybind11's signature line in its
docstring ("name(arg: type = default, ...) -> type"), overloads as typing.overload, enums as classes of
their values, the docstring kept. Types pybind11 prints that are not Python (NumPy arrays with shapes,
"float[3]") are written as their plain type; a default value is written as "...". A signature that still does
not parse as Python becomes (*args, **kwargs) -> Any, so the stub is always valid (tests/python/test_python_api.py).
"""
import ast
import inspect
import re
import sys

import uascma._uascma as core

MODULE = core.__name__


def clean_type(text):
    text = text.replace(f"{MODULE}.", "")
    text = re.sub(r"numpy\.ndarray\[[^\]]*(\[[^\]]*\])?[^\]]*\]", "numpy.ndarray", text)
    text = re.sub(r"\b(float|int|bool|str)\[[0-9, ]+\]", r"\1", text)
    text = re.sub(r"Annotated\[([^,\]]+\[[^\]]*\]|[^,\]]+), [^\]]*\]", r"\1", text)
    return text


def split_top(text, sep=","):
    """Splits at `sep` outside brackets and quotes."""
    parts, depth, quote, current = [], 0, None, ""
    for ch in text:
        if quote:
            current += ch
            if ch == quote:
                quote = None
            continue
        if ch in "'\"":
            quote = ch
        elif ch in "([{":
            depth += 1
        elif ch in ")]}":
            depth -= 1
        elif ch == sep and depth == 0:
            parts.append(current)
            current = ""
            continue
        current += ch
    if current.strip():
        parts.append(current)
    return parts


def signature_lines(name, doc):
    """The pybind11 signature(s) of `name` in its docstring: a list of (params text, return text)."""
    if not doc:
        return []
    found = []
    for line in doc.splitlines():
        line = re.sub(r"^\d+\. ", "", line.strip())
        if line.startswith(name + "(") and ")" in line:
            head = line[len(name) + 1:]
            depth, end = 1, None
            for i, ch in enumerate(head):
                depth += ch == "("
                depth -= ch == ")"
                if depth == 0:
                    end = i
                    break
            if end is None:
                continue
            rest = head[end + 1:].strip()
            ret = rest[2:].strip() if rest.startswith("->") else "Any"
            found.append((head[:end], ret))
    return found


def render_params(params):
    out = []
    for part in split_top(params):
        part = part.strip()
        if part in ("*", "/") or part.startswith("*"):
            out.append(part)
            continue
        name, _, rest = part.partition(":")
        typ, eq, _default = rest.partition("=")
        text = f"{name.strip()}: {clean_type(typ.strip())}" if typ.strip() else name.strip()
        out.append(text + (" = ..." if eq else ""))
    return ", ".join(out)


def docstring_body(name, doc):
    lines = [line for line in (doc or "").splitlines()
             if not re.sub(r"^\d+\. ", "", line.strip()).startswith(name + "(") and line.strip() != "Overloaded function."]
    text = "\n".join(lines).strip()
    return text.replace("\\", "\\\\").replace('"""', "'''")


def valid(code):
    try:
        ast.parse(code)
        return True
    except SyntaxError:
        return False


def function_stub(name, obj, indent, is_method=False):
    doc = getattr(obj, "__doc__", None)
    signatures = signature_lines(name, doc)
    pad = " " * indent
    body = docstring_body(name, doc)
    doc_line = f'{pad}    """{body}"""\n' if body else ""
    if not signatures:
        params = "self, *args: Any, **kwargs: Any" if is_method else "*args: Any, **kwargs: Any"
        return f"{pad}def {name}({params}) -> Any:\n{doc_line}{pad}    ...\n"
    out = []
    for params, ret in signatures:
        decorator = f"{pad}@overload\n" if len(signatures) > 1 else ""
        code = f"def {name}({render_params(params)}) -> {clean_type(ret)}: ...\n"
        if not valid(code):
            fallback = "self, *args: Any, **kwargs: Any" if is_method else "*args: Any, **kwargs: Any"
            code = f"def {name}({fallback}) -> Any: ...\n"
        out.append(decorator + pad + code.replace(": ...\n", ":\n") + doc_line + f"{pad}    ...\n")
    return "".join(out)


def property_stub(name, prop, indent):
    pad = " " * indent
    getter = prop.fget
    ret = "Any"
    sigs = signature_lines("(", None)
    doc = getattr(getter, "__doc__", "") or ""
    match = re.search(r"\)\s*->\s*(.+)$", doc.splitlines()[0]) if doc else None
    if match:
        ret = clean_type(match.group(1).strip())
        if not valid(f"x: {ret}\n"):
            ret = "Any"
    del sigs
    text = f"{pad}@property\n{pad}def {name}(self) -> {ret}: ...\n"
    if prop.fset is not None:
        text += f"{pad}@{name}.setter\n{pad}def {name}(self, value: {ret}) -> None: ...\n"
    return text


def class_stub(name, cls):
    bases = [b.__name__ for b in cls.__bases__ if b.__module__ == MODULE]
    if issubclass(cls, BaseException):
        base = cls.__bases__[0]
        return f"class {name}({base.__name__}): ...\n"
    header = f"class {name}({', '.join(bases)}):\n" if bases else f"class {name}:\n"
    body = []
    doc = (cls.__doc__ or "").strip().replace('"""', "'''")
    if doc:
        body.append(f'    """{doc}"""\n')
    members = getattr(cls, "__members__", None)
    if isinstance(members, dict) and members:
        for value in members:
            body.append(f"    {value}: {name}\n")
        body.append("    def __init__(self, value: int) -> None: ...\n")
        body.append("    def __int__(self) -> int: ...\n    def __index__(self) -> int: ...\n")
        body.append("    @property\n    def name(self) -> str: ...\n    @property\n    def value(self) -> int: ...\n")
        body.append(f"    __members__: Dict[str, {name}]\n")
        return header + "".join(body)
    for attr, value in sorted(vars(cls).items()):
        if attr.startswith("_") and attr not in ("__init__", "__call__", "__iter__", "__len__", "__getitem__",
                                                   "__eq__", "__repr__"):
            continue
        if isinstance(value, property):
            body.append(property_stub(attr, value, 4))
        elif isinstance(value, staticmethod):
            body.append("    @staticmethod\n" + function_stub(attr, value.__func__, 4))
        elif callable(value) and type(value).__name__ in ("instancemethod", "builtin_function_or_method",
                                                           "method_descriptor", "wrapper_descriptor"):
            if type(value).__name__ == "builtin_function_or_method":  # pybind11 static method
                body.append("    @staticmethod\n" + function_stub(attr, value, 4))
            else:
                body.append(function_stub(attr, value, 4, is_method=True))
    if not body:
        body.append("    ...\n")
    return header + "".join(body)


def main(out_path):
    parts = [
        '"""Type stub of uascma._uascma (written by python/tools/make_stubs.py from the built module)."""\n',
        "from typing import Any, Callable, Dict, Iterable, Iterator, List, Optional, Sequence, Tuple, Union, "
        "overload\n",
        "import os\n",
        "import numpy\n\n",
    ]
    classes, functions, constants = [], [], []
    for name, value in sorted(vars(core).items()):
        if name.startswith("_") and name != "__version__":
            continue
        if inspect.isclass(value):
            classes.append((name, value))
        elif callable(value):
            functions.append((name, value))
        elif isinstance(value, (int, float, str)):
            constants.append((name, value))
    for name, value in constants:
        parts.append(f"{name}: {type(value).__name__}\n")
    parts.append("\n")
    # Base classes first.
    ordered, seen = [], set()

    def visit(name, cls):
        if name in seen:
            return
        for base in cls.__bases__:
            if base.__module__ == MODULE and base.__name__ in vars(core):
                visit(base.__name__, base)
        seen.add(name)
        ordered.append((name, cls))

    for name, cls in classes:
        visit(name, cls)
    for name, cls in ordered:
        parts.append(class_stub(name, cls) + "\n")
    for name, fn in functions:
        parts.append(function_stub(name, fn, 0) + "\n")
    text = "".join(parts)
    ast.parse(text)  # the stub is Python
    with open(out_path, "w") as f:
        f.write(text)


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])

#!/usr/bin/env python3
"""Generates uascma's MAVLink v2 message codec from the official XML message definitions.

    python3 scripts/mavlink_generate.py DEFINITIONS.xml OUTPUT.h [--table]

Reads DEFINITIONS.xml and every file it <include>s (relative to it), and writes one C++ header with, for each
message, a struct whose members are the message's fields, its id, CRC_EXTRA, minimum and maximum payload
length, and a VisitWire() that walks the fields in wire order; for each enum entry a constant. --table prints
the messages (id, name, CRC_EXTRA, lengths, wire order) instead, for a reader to check.

The rules are those of the MAVLink serialisation specification (mavlink.io, "Serialization"):
- wire order: the base fields sorted by the size of their element type, largest first, a stable sort (fields of
  one size keep their XML order); arrays sort by their element's size. Extension fields (after <extensions/>) are
  not sorted: they follow the base fields in XML order.
- CRC_EXTRA: the X.25 CRC (CRC-16/MCRF4XX: polynomial 0x1021 reflected, initial 0xFFFF) of the message name and a
  space, then, for each base field in wire order, its type and a space, its name and a space, and for an array
  its length as one byte; the two bytes of that CRC XORed. Extensions do not enter it.
- the minimum length is that of the base fields, the maximum that with the extensions.
"""
import argparse
import os
import sys
import xml.etree.ElementTree as ElementTree

# Element types of the XML and their C++ types and sizes in bytes.
TYPES = {
    "char": ("char", 1), "uint8_t": ("std::uint8_t", 1), "int8_t": ("std::int8_t", 1),
    "uint16_t": ("std::uint16_t", 2), "int16_t": ("std::int16_t", 2),
    "uint32_t": ("std::uint32_t", 4), "int32_t": ("std::int32_t", 4), "float": ("float", 4),
    "uint64_t": ("std::uint64_t", 8), "int64_t": ("std::int64_t", 8), "double": ("double", 8),
    "uint8_t_mavlink_version": ("std::uint8_t", 1),
}


class Field:
    def __init__(self, element, extension):
        self.name = element.get("name")
        text = element.get("type")
        self.array_length = 0
        if "[" in text:
            text, length = text.rstrip("]").split("[")
            self.array_length = int(length)
        if text not in TYPES:
            raise SystemExit(f"mavlink_generate: field {self.name}: unknown type {text}")
        self.xml_type = text
        self.cpp_type, self.element_size = TYPES[text]
        self.extension = extension
        self.units = element.get("units", "")
        self.enum = element.get("enum", "")

    @property
    def size(self):
        return self.element_size * max(1, self.array_length)

    @property
    def crc_type(self):  # the type as CRC_EXTRA spells it: mavlink_version's special type is a uint8_t
        return "uint8_t" if self.xml_type == "uint8_t_mavlink_version" else self.xml_type


class Message:
    def __init__(self, element):
        self.id = int(element.get("id"))
        self.name = element.get("name")
        self.description = " ".join((element.findtext("description") or "").split())
        self.fields = []
        extension = False
        for child in element:
            if child.tag == "extensions":
                extension = True
            elif child.tag == "field":
                self.fields.append(Field(child, extension))
        base = [f for f in self.fields if not f.extension]
        extensions = [f for f in self.fields if f.extension]
        self.wire = sorted(base, key=lambda f: -f.element_size) + extensions
        self.min_length = sum(f.size for f in base)
        self.max_length = sum(f.size for f in self.fields)
        self.crc_extra = calc_crc_extra(self.name, [f for f in self.wire if not f.extension])


def crc_accumulate(byte, crc):
    """One byte into the X.25 CRC (the MAVLink checksum)."""
    tmp = (byte ^ (crc & 0xFF)) & 0xFF
    tmp = (tmp ^ (tmp << 4)) & 0xFF
    return ((crc >> 8) ^ (tmp << 8) ^ (tmp << 3) ^ (tmp >> 4)) & 0xFFFF


def calc_crc_extra(name, base_wire_fields):
    crc = 0xFFFF
    data = bytearray((name + " ").encode("ascii"))
    for field in base_wire_fields:
        data += (field.crc_type + " ").encode("ascii")
        data += (field.name + " ").encode("ascii")
        if field.array_length:
            data.append(field.array_length)
    for b in data:
        crc = crc_accumulate(b, crc)
    return (crc & 0xFF) ^ (crc >> 8)


def read_definitions(path, seen=None):
    """Messages and enums of `path` and of every file it includes, each file read once."""
    seen = set() if seen is None else seen
    path = os.path.realpath(path)
    if path in seen:
        return [], {}
    seen.add(path)
    root = ElementTree.parse(path).getroot()
    messages, enums = [], {}
    for include in root.findall("include"):
        sub_messages, sub_enums = read_definitions(os.path.join(os.path.dirname(path), include.text.strip()), seen)
        messages += sub_messages
        for name, entries in sub_enums.items():
            enums.setdefault(name, []).extend(entries)
    for element in root.iter("message"):
        messages.append(Message(element))
    for element in root.iter("enum"):
        entries = [(e.get("name"), int(e.get("value"), 0)) for e in element.findall("entry")]
        enums.setdefault(element.get("name"), []).extend(entries)
    return messages, enums


def camel(name):
    return "".join(part.capitalize() for part in name.lower().split("_"))


def member_type(field):
    if field.array_length:
        return f"std::array<{field.cpp_type}, {field.array_length}>"
    return field.cpp_type


def emit_message(message, version):
    out = []
    if message.description:
        out.append(f"// {message.name}: {message.description}")
    out.append(f"struct {camel(message.name)} {{")
    out.append(f"  static constexpr std::uint32_t kId = {message.id};")
    out.append(f'  static constexpr const char* kName = "{message.name}";')
    out.append(f"  static constexpr std::uint8_t kCrcExtra = {message.crc_extra};")
    out.append(f"  static constexpr std::size_t kMinLength = {message.min_length};  // bytes, the base fields")
    out.append(f"  static constexpr std::size_t kMaxLength = {message.max_length};  // bytes, with the extensions")
    for field in message.fields:
        initial = "{}"
        if field.xml_type == "uint8_t_mavlink_version":
            initial = f"{{{version}}}"
        notes = []
        if field.units:
            notes.append(field.units)
        if field.enum:
            notes.append(field.enum)
        if field.extension:
            notes.append("extension")
        comment = f"  // {', '.join(notes)}" if notes else ""
        out.append(f"  {member_type(field)} {field.name}{initial};{comment}")
    names = ", ".join(f.name for f in message.wire)
    out.append("  // The fields in wire order (by element size, extensions last): f(field) for each.")
    for qualifier in ("", " const"):
        out.append(f"  template <class F>")
        out.append(f"  void VisitWire(F&& f){qualifier} {{")
        for field in message.wire:
            out.append(f"    f({field.name});")
        out.append("  }")
    out.append(f"  bool operator==(const {camel(message.name)}&) const = default;")
    out.append("};")
    return out


def emit_header(messages, enums, sources, version):
    out = [
        "#pragma once",
        "// GENERATED by scripts/mavlink_generate.py from " + ", ".join(sources) + ": do not edit.",
        "// The MAVLink v2 messages uascma speaks: one struct per message (its fields, id, CRC_EXTRA, payload lengths",
        "// and VisitWire in wire order) and one constant per enum entry. The byte-level codec is mavlink/codec.h.",
        "#include <array>",
        "#include <cstddef>",
        "#include <cstdint>",
        "#include <tuple>",
        "",
        "namespace uascma::mavlink {",
        "",
        "// ---- enums ----",
    ]
    for name in sorted(enums):
        out.append(f"// {name}")
        for entry, value in enums[name]:
            out.append(f"inline constexpr std::uint32_t k{camel(entry)} = {value};")
    out.append("")
    out.append("// ---- messages ----")
    for message in sorted(messages, key=lambda m: m.id):
        out += emit_message(message, version)
        out.append("")
    ordered = sorted(messages, key=lambda m: m.id)
    out.append("// Every message above, by id.")
    out.append("using AllMessages = std::tuple<" + ", ".join(camel(m.name) for m in ordered) + ">;")
    out.append("")
    out.append("// What the frame parser needs of a message: its id, name, CRC_EXTRA and payload lengths.")
    out.append("struct MessageInfo {")
    out.append("  std::uint32_t id;")
    out.append("  const char* name;")
    out.append("  std::uint8_t crc_extra;")
    out.append("  std::size_t min_length, max_length;  // bytes")
    out.append("};")
    out.append(f"inline constexpr std::array<MessageInfo, {len(ordered)}> kMessageInfos{{{{")
    for m in ordered:
        out.append(f'    {{{m.id}, "{m.name}", {m.crc_extra}, {m.min_length}, {m.max_length}}},')
    out.append("}};")
    out.append("")
    out.append("}  // namespace uascma::mavlink")
    return "\n".join(out) + "\n"


def dialect_version(path):
    root = ElementTree.parse(path).getroot()
    return int(root.findtext("version") or "0")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("definitions")
    parser.add_argument("output", nargs="?")
    parser.add_argument("--table", action="store_true")
    args = parser.parse_args()
    messages, enums = read_definitions(args.definitions)
    ids = [m.id for m in messages]
    if len(set(ids)) != len(ids):
        raise SystemExit("mavlink_generate: a message id is defined twice")
    if args.table:
        for m in sorted(messages, key=lambda m: m.id):
            order = " ".join(f.name + ("*" if f.extension else "") for f in m.wire)
            print(f"{m.id}\t{m.name}\t{m.crc_extra}\t{m.min_length}\t{m.max_length}\t{order}")
        return 0
    if not args.output:
        raise SystemExit("mavlink_generate: OUTPUT.h is required without --table")
    text = emit_header(messages, enums, ["data/mavlink/" + os.path.basename(args.definitions) + " and its includes"],
                       dialect_version(args.definitions))
    os.makedirs(os.path.dirname(os.path.abspath(args.output)), exist_ok=True)
    previous = None
    if os.path.exists(args.output):
        with open(args.output, encoding="utf-8") as f:
            previous = f.read()
    if previous != text:  # an unchanged header keeps its time stamp: nothing that includes it rebuilds
        with open(args.output + ".tmp", "w", encoding="utf-8") as f:
            f.write(text)
        os.replace(args.output + ".tmp", args.output)
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""Replaces every .vtu file under the given folders by `<name>.vtu.decoded`: the file's XML
elements and attributes in order (without `format` and `offset`, which only say how an array is
encoded) and each data array's values, floats as the hex of their 64 bits. A VTU file written in
ASCII and the same written in binary decode to the same text exactly when they hold the same
values bit for bit, so `diff` compares the numbers, not the encoding (scripts/same_outputs.sh).

Reads the encodings crates/io/src/vtu.rs writes: ASCII, inline base64 (`format="binary"`) and
appended raw data, uncompressed or in zlib blocks (`compressor="vtkZLibDataCompressor"`, which is
left out of the decoded text like `format`), Float64, Int64 or UInt8 with UInt64 byte counts.
Standard library only.

Usage: python3 scripts/vtu_decode.py FOLDER...
"""
import base64
import struct
import sys
import xml.etree.ElementTree as ET
import zlib
from pathlib import Path

TYPES = {"Float64": "d", "Int64": "q", "UInt8": "B"}


def split(data: bytes):
    """The XML (closed) and the raw appended bytes after the underscore, or None."""
    at = data.find(b"<AppendedData")
    if at < 0:
        return data.decode("utf-8"), None
    end = data.index(b">", at)
    rest = data[end + 1:].lstrip()
    assert rest.startswith(b"_"), "appended data without '_'"
    return data[:at].decode("utf-8") + "</VTKFile>", rest[1:]


def block(raw: bytes, offset: int) -> bytes:
    (count,) = struct.unpack_from("<Q", raw, offset)
    data = raw[offset + 8:offset + 8 + count]
    assert len(data) == count, f"block at {offset}: short"
    return data


def zlib_block(raw: bytes, offset: int) -> bytes:
    """The data of the vtkZLibDataCompressor block at `offset`: the number of blocks, the block
    size, the last block's size, each block's compressed size (UInt64), then the zlib streams."""
    count, size, last = struct.unpack_from("<3Q", raw, offset)
    sizes = struct.unpack_from(f"<{count}Q", raw, offset + 24)
    start = offset + 24 + 8 * count
    parts = []
    for k, packed in enumerate(sizes):
        part = zlib.decompress(raw[start:start + packed])
        assert len(part) == (last if k + 1 == count and last else size), f"block at {offset}: size"
        parts.append(part)
        start += packed
    return b"".join(parts)


def values(element, raw, compressed) -> list[str]:
    ty = element.get("type")
    code = TYPES[ty]
    form = element.get("format")
    if form == "ascii":
        numbers = (element.text or "").split()
        if ty == "Float64":
            return [f"{struct.unpack('<Q', struct.pack('<d', float(v)))[0]:016x}" for v in numbers]
        return [str(int(v)) for v in numbers]
    if form == "binary":
        data = block(base64.b64decode("".join((element.text or "").split())), 0)
    elif compressed:
        data = zlib_block(raw, int(element.get("offset")))
    else:
        data = block(raw, int(element.get("offset")))
    size = struct.calcsize(code)
    if ty == "Float64":
        return [f"{v:016x}" for (v,) in struct.iter_unpack("<Q", data)]
    return [str(v) for (v,) in struct.iter_unpack("<" + code, data[:len(data) // size * size])]


def decoded(path: Path) -> str:
    text, raw = split(path.read_bytes())
    lines = []
    root = ET.fromstring(text)
    compressed = root.get("compressor") == "vtkZLibDataCompressor"
    encoding = ("format", "offset", "compressor")

    def walk(element, depth):
        attributes = {k: v for k, v in element.attrib.items() if k not in encoding}
        lines.append("  " * depth + element.tag + " " + repr(sorted(attributes.items())))
        if element.tag == "DataArray":
            lines.extend(values(element, raw, compressed))
        for child in element:
            walk(child, depth + 1)

    walk(root, 0)
    return "\n".join(lines) + "\n"


def main() -> None:
    for folder in sys.argv[1:]:
        for path in sorted(Path(folder).rglob("*.vtu")):
            path.with_name(path.name + ".decoded").write_text(decoded(path))
            path.unlink()


if __name__ == "__main__":
    main()

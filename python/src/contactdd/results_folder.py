"""Reading a result folder back: :func:`load_results`.

A result folder is what ``contactdd solve --out DIR``, ``contactdd monolithic --out DIR``,
:meth:`Result.write_vtu` or :meth:`MonolithicResult.write_vtu` write (``docs/outputs.md``). It
holds a complete result exactly when ``summary.json`` exists, and then only the files its
manifest (the ``files`` key) lists belong to it. This module reads such a folder into the result
objects :func:`contactdd.solve` and :func:`contactdd.monolithic` return: the fields of every body
from its VTU file (one per body, or one for all bodies with a piece each), the contact tables
and everything else from ``summary.json``, the iteration history from ``history.csv``. Only the
standard library and numpy are used.

The folder is untrusted input: every file is read by the reader ``contactdd plot`` uses, which
follows no symbolic link, opens no FIFO or device and reads at most 256 MiB of a JSON or CSV file
and 1 GiB of a VTU file (a larger one is refused); a manifest may name only plain file names of
the folder; and a file not as contactdd writes it gives a :class:`ContactddError`.
"""

from __future__ import annotations

import base64
import csv
import errno as errno_codes
import json
import os
import xml.etree.ElementTree as ET
import zlib
from pathlib import Path
from typing import Any, Union

import numpy as np

from ._contactdd import (
    Body,
    Contact,
    ContactddError,
    ContactddIOError,
    MonolithicResult,
    Result,
    SpaceBody,
    SpaceResult,
    _read_result_file,
)

__all__ = ["load_results"]

#: VTK cell types of the meshes contactdd writes: nodes per cell (triangles 5 and 22 in the
#: plane, tetrahedra 10 and 24 in space).
_CELL_NODES = {5: 3, 22: 6, 10: 4, 24: 10}
#: The nodes of VTK's quadratic tetrahedron (type 24) in Gmsh's order, which the bodies use: the
#: mid-edge nodes of the edges 2-3 and 1-3 are swapped (crates/io/src/solid_vtu.rs).
_VTK_TET10_TO_GMSH = [0, 1, 2, 3, 4, 5, 6, 7, 9, 8]
#: The header of contact.csv of a result in space.
_SPACE_CONTACT = ["pair", "body", "node", "x", "y", "z", "weight", "gap", "pressure"]
#: The columns it adds when a pair is frictional (the last one text, the others numbers, empty
#: at a frictionless pair's points).
_SPACE_FRICTION = ["traction_x", "traction_y", "traction_z", "slip_x", "slip_y", "slip_z",
                   "status"]
_DTYPES = {"Float64": np.float64, "Float32": np.float32, "Int64": np.int64, "UInt8": np.uint8}
#: The largest uncompressed size of a zlib block read, relative to its compressed size (deflate
#: expands by at most 1032 times), and in bytes: the bounds of crates/io/src/vtu_read.rs.
_MAX_EXPANSION = 1040
_MAX_BLOCK = 1 << 30


def load_results(
    directory: Union[str, "os.PathLike[str]"],
) -> Union[Result, MonolithicResult, SpaceResult]:
    """Reads a result folder back into the result object of the solve that wrote it.

    A folder of a domain decomposition solve gives a :class:`Result`, one of a monolithic solve a
    :class:`MonolithicResult`, with the attributes the solve's result had (for a folder of load
    steps: the last step, with its ``load_factor``), so plots and analysis work on saved runs.
    Its :meth:`~Result.summary` is the folder's ``summary.json`` without the manifest; it cannot
    :meth:`~Result.write_vtu` again. A folder of a problem in space (``"dimension": 3`` in
    ``summary.json``, by either solver) gives a :class:`contactdd.space.Result`, its bodies read
    from the ``.vtu`` files of tetrahedra and its contact points from ``contact.csv``.

    Args:
        directory: the result folder.

    Returns:
        A :class:`Result`, :class:`MonolithicResult` or :class:`contactdd.space.Result`.

    Raises:
        ContactddIOError: the folder or one of its files cannot be read, or ``directory`` is a
            file (an ``OSError``); also a file of the folder that is a symbolic link, a FIFO, a
            device or a folder, or larger than its limit (256 MiB for JSON and CSV, 1 GiB for
            VTU); the message names the file.
        ContactddError: ``directory`` is not a path, the folder holds no complete result (no ``summary.json``: the write was
            interrupted or this is not a result folder; a file of the manifest is missing), or a
            file is not what contactdd writes.
    """
    if not isinstance(directory, (str, os.PathLike)):
        raise ContactddError(
            f"directory: expected a path, got a value of type {type(directory).__name__}"
        )
    folder = Path(directory)
    summary = _read_summary(folder)
    try:
        return _load(folder, summary)
    except ContactddError:
        raise
    except (KeyError, ValueError, IndexError, TypeError, AttributeError, OverflowError,
            RecursionError, csv.Error) as e:
        # The specific checks name what is wrong; this names a file not as contactdd writes it
        # that they do not foresee.
        raise ContactddError(f"{folder}: not a result folder as contactdd writes it "
                             f"({type(e).__name__}: {e})") from e


def _load(folder: Path,
          summary: dict[str, Any]) -> Union[Result, MonolithicResult, SpaceResult]:
    files = summary.pop("files")
    for name in files:
        if not _plain(name):
            raise ContactddError(
                f"{folder}: summary.json lists {name!r}, which is not a file name of the folder"
            )
        if not os.path.lexists(folder / name):
            raise ContactddError(
                f"{folder}: incomplete result folder: summary.json lists '{name}', which is "
                "missing (write the results again)"
            )
    vtus = [name for name in files if name.endswith(".vtu")]
    infos = _key(summary, "bodies", folder)
    # The manifest lists the VTU files in body order, step after step, each file holding one
    # body (one piece) or every body of its step (one piece each): the last pieces are the
    # bodies of the last step, the one summary.json describes.
    pieces: list[tuple[Path, Union[bytes, None], ET.Element, bool]] = []
    for name in reversed(vtus):
        if len(pieces) >= len(infos):
            break
        pieces[:0] = _pieces(folder / name)
    if len(pieces) < len(infos):
        raise ContactddError(f"{folder}: summary.json lists VTU files of {len(pieces)} bodies "
                             f"for {len(infos)} bodies")
    last = pieces[len(pieces) - len(infos):]
    if summary.get("dimension") == 3:
        return _space(summary, files, last, infos, folder)
    bodies = [_body(piece, info) for piece, info in zip(last, infos)]
    names = [b["name"] for b in infos]
    contact = [_contact(p, folder) for p in _key(summary, "contact", folder)]
    if summary.get("solver") == "monolithic":
        return _monolithic(summary, bodies, contact, folder)
    return _result(summary, files, bodies, contact, names, folder)


def _plain(name: Any) -> bool:
    """True if ``name`` is a plain file name: one component, not ``.`` or ``..``."""
    return (isinstance(name, str) and name not in ("", ".", "..") and "/" not in name
            and "\\" not in name and "\0" not in name)


def _io_error(path: Path, e: OSError) -> ContactddIOError:
    error = ContactddIOError(f"cannot read '{path}': {e.strerror or e}")
    error.errno = e.errno
    return error


def _read_text(path: Path, kind: str = "text") -> str:
    """The UTF-8 text of ``path``, read by the reader of ``contactdd plot`` with the limit of
    ``kind`` (``"text"`` or ``"vtu"``)."""
    data = _read_result_file(os.fspath(path), kind)
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as e:
        raise ContactddError(f"{path}: not UTF-8 text (byte {e.start})") from e


def _read_summary(folder: Path) -> dict[str, Any]:
    if folder.exists() and not folder.is_dir():
        error = ContactddIOError(
            f"'{folder}' is not a results folder: it is a file (give the folder that "
            "contactdd solve --out or Result.write_vtu wrote)"
        )
        error.errno = errno_codes.ENOTDIR
        raise error
    if not folder.is_dir():
        e = OSError(errno_codes.ENOENT, os.strerror(errno_codes.ENOENT))
        raise _io_error(folder, e)
    path = folder / "summary.json"
    if not os.path.lexists(path):
        raise ContactddError(
            f"{folder}: no complete result: summary.json is missing (it is written last, so "
            "the write was interrupted, or this is not a result folder)"
        )
    try:
        summary = json.loads(_read_text(path))
    except (json.JSONDecodeError, RecursionError) as e:
        raise ContactddError(f"{path}: not a summary written by contactdd: {e}") from e
    if not isinstance(summary, dict) or not isinstance(summary.get("files"), list):
        raise ContactddError(f"{path}: no manifest ('files'): not a result folder of contactdd")
    return summary


def _key(d: dict[str, Any], key: str, where: Path) -> Any:
    if key not in d:
        raise ContactddError(
            f"{where}: summary.json has no '{key}' (written by another version of contactdd?)"
        )
    return d[key]


def _floats(values: Any) -> np.ndarray:
    """A JSON list of numbers as floats, ``null`` (a non-finite value) as NaN."""
    return np.array([np.nan if v is None else v for v in values], dtype=np.float64)


def _number(v: Any) -> float:
    return float("nan") if v is None else float(v)


def _split_appended(data: bytes) -> tuple[str, Union[bytes, None]]:
    """The XML of a VTU file and the raw bytes of its ``<AppendedData encoding="raw">`` section
    (after the ``_``), or ``None`` when it has none."""
    at = data.find(b"<AppendedData")
    if at < 0:
        return data.decode("utf-8"), None
    end = data.find(b">", at)
    if end < 0:
        raise ValueError("the AppendedData tag is not closed")
    if b'encoding="raw"' not in data[at:end]:
        raise ValueError('appended data is not raw (only encoding="raw" is read)')
    rest = data[end + 1:].lstrip()
    if not rest.startswith(b"_"):
        raise ValueError("the appended data does not start with '_'")
    # The XML before the section, closed, parses alone.
    return data[:at].decode("utf-8") + "</VTKFile>", rest[1:]


def _block(raw: bytes, offset: int) -> bytes:
    """The data of the block at ``offset``: a UInt64 byte count, then that many bytes, all of
    which must be there (a count or offset past the end of the file is an error, so no
    allocation exceeds the file)."""
    if offset < 0 or offset + 8 > len(raw):
        raise ValueError(f"block at {offset}: past the end of the data")
    count = int.from_bytes(raw[offset:offset + 8], "little")
    if count > len(raw) - offset - 8:
        raise ValueError(f"block at {offset}: {count} bytes declared, more than the file holds")
    return raw[offset + 8:offset + 8 + count]


def _word(raw: bytes, at: int) -> int:
    if at < 0 or at + 8 > len(raw):
        raise ValueError(f"header word at {at}: past the end of the data")
    return int.from_bytes(raw[at:at + 8], "little")


def _zlib_block(raw: bytes, offset: int) -> bytes:
    """The uncompressed data of the zlib-compressed block at ``offset`` (VTK's
    vtkZLibDataCompressor layout): UInt64 words (the number of blocks n, the uncompressed block
    size, the size of a shorter last block or 0, the n compressed sizes), then the n zlib
    streams. Every size is checked against the file and the bounds above before anything is
    decompressed, and each stream is decompressed to at most its declared size, which it must
    fill exactly."""
    count, size, last = (_word(raw, offset + 8 * k) for k in range(3))
    if count > len(raw) // 8:
        raise ValueError(f"block at {offset}: {count} compressed blocks, more than the file holds")
    if count and (size == 0 or size > _MAX_BLOCK or last > size):
        raise ValueError(f"block at {offset}: bad sizes ({size} per block, {last} in the last)")
    start = offset + 8 * (3 + count)
    parts = []
    for k in range(count):
        packed = _word(raw, offset + 8 * (3 + k))
        if packed > len(raw) - start:
            raise ValueError(f"block at {offset}: compressed block {k} past the end of the file")
        unpacked = last if k + 1 == count and last else size
        if unpacked > packed * _MAX_EXPANSION:
            raise ValueError(f"block at {offset}: block {k} declares more than zlib can expand")
        inflate = zlib.decompressobj()
        try:
            data = inflate.decompress(raw[start:start + packed], unpacked)
        except zlib.error as e:
            raise ValueError(f"block at {offset}: compressed block {k}: {e}") from e
        if (len(data) != unpacked or not inflate.eof or inflate.unconsumed_tail
                or inflate.unused_data):
            raise ValueError(f"block at {offset}: compressed block {k} is not one zlib stream "
                             f"of the {unpacked} bytes declared")
        parts.append(data)
        start += packed
    return b"".join(parts)


def _data_array(element: ET.Element, raw: Union[bytes, None] = None,
                compressed: bool = False) -> np.ndarray:
    """The values of a VTU ``DataArray``: ASCII, base64 binary with a UInt64 byte count, or a
    block of the raw appended data ``raw``, zlib-compressed when ``compressed``."""
    dtype = np.dtype(_DTYPES[element.get("type", "Float64")]).newbyteorder("<")
    text = element.text or ""
    form = element.get("format")
    if form == "binary":
        if compressed:
            raise ValueError(f"{element.get('Name')}: compressed inline base64 is not read")
        data = _block(base64.b64decode("".join(text.split()), validate=True), 0)
        values = np.frombuffer(data, dtype=dtype).astype(dtype.newbyteorder("="))
    elif form == "appended":
        if raw is None:
            raise ValueError(f"{element.get('Name')}: appended, but the file has no AppendedData")
        offset = int(element.get("offset", ""))
        data = _zlib_block(raw, offset) if compressed else _block(raw, offset)
        values = np.frombuffer(data, dtype=dtype).astype(dtype.newbyteorder("="))
    else:
        floats = np.array([float(v) for v in text.split()])
        if dtype.kind in "iu" and not np.all(np.isfinite(floats) & (floats == np.round(floats))
                                            & (np.abs(floats) < 2**53)):
            raise ValueError(f"{element.get('Name')}: integers expected")
        values = floats.astype(dtype.newbyteorder("="))
    components = int(element.get("NumberOfComponents", "1"))
    return values.reshape(-1, components) if components > 1 else values


def _pieces(path: Path) -> list[tuple[Path, Union[bytes, None], ET.Element, bool]]:
    """The ``Piece`` elements of the VTU file ``path``, one per body it holds, each with the
    file's path, its raw appended bytes and whether they are zlib-compressed."""
    data = _read_result_file(os.fspath(path), "vtu")
    try:
        text, raw = _split_appended(data)
        root = ET.fromstring(text)
        compressor = root.get("compressor")
        if compressor not in (None, "vtkZLibDataCompressor"):
            raise ValueError(f"compressor {compressor!r} is not read (only vtkZLibDataCompressor)")
        compressed = compressor is not None
        if compressed and root.get("header_type") != "UInt64":
            raise ValueError('zlib-compressed arrays need header_type="UInt64"')
        pieces = root.findall("./UnstructuredGrid/Piece")
        if not pieces:
            raise ValueError("no Piece")
    except (ET.ParseError, ValueError, UnicodeDecodeError) as e:
        raise ContactddError(f"{path}: not a VTU file of contactdd ({type(e).__name__}: {e})") from e
    return [(path, raw, piece, compressed) for piece in pieces]


def _body(piece: tuple[Path, Union[bytes, None], ET.Element, bool],
          info: dict[str, Any]) -> Union[Body, SpaceBody]:
    path, raw, element, compressed = piece
    try:
        if "imbalance" in info and "tetrahedra" in info:
            return _parse_space_body(element, raw, compressed, info)
        return _parse_body(element, raw, compressed, info)
    except (KeyError, ValueError, IndexError, TypeError) as e:
        raise ContactddError(f"{path}: not a VTU file of contactdd ({type(e).__name__}: {e})") from e


def _parse_body(piece: ET.Element, raw: Union[bytes, None], compressed: bool,
                info: dict[str, Any]) -> Body:
    """The body of the ``Piece`` element ``piece`` (``raw``: its file's appended bytes)."""
    arrays = {a.get("Name"): _data_array(a, raw, compressed) for a in piece.iter("DataArray")}
    points = piece.find("./Points/DataArray")
    if points is None:
        raise ValueError("no Points")
    types = arrays["types"]
    per_cell = _CELL_NODES[int(types[0])] if len(types) else 3
    stress = np.column_stack([arrays[f"sigma_{c}"] for c in ["xx", "yy", "xy", "zz"]])
    return Body._from_state({
        "name": info["name"],
        "order": info["order"],
        "condensation": info.get("condensation"),
        "nodes": np.ascontiguousarray(_data_array(points, raw, compressed)[:, :2]),
        "triangles": arrays["connectivity"].reshape(-1, per_cell),
        "displacement": np.ascontiguousarray(arrays["displacement"][:, :2]),
        "stress": stress,
        "von_mises": arrays["von_mises"],
        # The body's σ_n ≤ 0 at its contact nodes; the file's contact_pressure is p ≥ 0.
        "contact_pressure": arrays["sigma_n"],
    })


def _parse_space_body(piece: ET.Element, raw: Union[bytes, None], compressed: bool,
                      info: dict[str, Any]) -> SpaceBody:
    """The tetrahedral body of the ``Piece`` element ``piece``, its P2 tetrahedra put back into
    Gmsh's node order."""
    arrays = {a.get("Name"): _data_array(a, raw, compressed) for a in piece.iter("DataArray")}
    points = piece.find("./Points/DataArray")
    if points is None:
        raise ValueError("no Points")
    types = arrays["types"]
    if len(types) == 0 or np.any(types != types[0]) or int(types[0]) not in (10, 24):
        raise ValueError("expected tetrahedra of one VTK type, 10 or 24")
    tetrahedra = arrays["connectivity"].astype(np.int64).reshape(-1, _CELL_NODES[int(types[0])])
    if int(types[0]) == 24:
        tetrahedra = np.ascontiguousarray(tetrahedra[:, _VTK_TET10_TO_GMSH])
    tensor = arrays["stress"].reshape(-1, 9)
    return SpaceBody._from_state({
        "name": info["name"],
        "order": info["order"],
        "nodes": np.ascontiguousarray(_data_array(points, raw, compressed).reshape(-1, 3)),
        "tetrahedra": tetrahedra,
        "displacement": np.ascontiguousarray(arrays["displacement"].reshape(-1, 3)),
        # The 3 × 3 tensor (xx xy xz yx yy yz zx zy zz) as Voigt [xx, yy, zz, yz, xz, xy].
        "stress": np.ascontiguousarray(tensor[:, [0, 4, 8, 5, 2, 1]]),
        "von_mises": arrays["von_mises"],
        "imbalance": _number(info["imbalance"]),
    })


def _space_contact(path: Path) -> dict[str, np.ndarray]:
    """``contact.csv`` of a result in space: its columns as numpy arrays."""
    try:
        lines = list(csv.reader(_read_text(path).splitlines()))
    except csv.Error as e:
        raise ContactddError(f"{path}: not a CSV file of contactdd: {e}") from e
    header = lines[0] if lines else []
    if header not in (_SPACE_CONTACT, _SPACE_CONTACT + _SPACE_FRICTION):
        raise ContactddError(f"{path}: expected the header {','.join(_SPACE_CONTACT)} "
                             f"(and with friction {','.join(_SPACE_FRICTION)})")
    rows = lines[1:]
    if any(len(r) != len(header) for r in rows):
        raise ContactddError(f"{path}: expected {len(header)} columns")
    columns = list(zip(*rows)) if rows else [()] * len(header)
    table: dict[str, np.ndarray] = {
        "pair": np.array(columns[0], dtype=str),
        "body": np.array(columns[1], dtype=str),
    }
    try:
        table["node"] = np.array([int(v) for v in columns[2]], dtype=np.int64)
        for name, values in zip(header[3:], columns[3:]):
            if name == "status":
                table[name] = np.array(values, dtype=str)
                continue
            # A frictionless pair's points leave the friction columns empty.
            empty = np.nan if name in _SPACE_FRICTION else None
            table[name] = np.array([float(v) if v or empty is None else empty for v in values],
                                   dtype=np.float64)
    except (ValueError, OverflowError) as e:
        raise ContactddError(f"{path}: not a CSV file of contactdd: {e}") from e
    return table


def _space(summary: dict[str, Any], files: list[str],
           pieces: list[tuple[Path, Union[bytes, None], ET.Element, bool]],
           infos: list[dict[str, Any]], folder: Path) -> SpaceResult:
    """The result of a problem in space: bodies from the VTU pieces, contact points from
    contact.csv, the rest from summary.json."""
    if "contact.csv" not in files:
        raise ContactddError(f"{folder}: summary.json lists no contact.csv")
    bodies = [_body(piece, info) for piece, info in zip(pieces, infos)]
    balance = _key(summary, "balance", folder)
    # A frictional result also checks the friction law.
    checks = ("worst", "tol", "contact_law") + (("friction_law",) if "friction_law" in balance
                                                else ())
    return SpaceResult._from_state({
        "converged": bool(_key(summary, "converged", folder)),
        "reason": _key(summary, "reason", folder),
        "solver": _key(summary, "solver", folder),
        "newton_steps": _key(summary, "newton_steps", folder),
        "bodies": bodies,
        "contact": _space_contact(folder / "contact.csv"),
        "balance": {k: _number(balance[k]) for k in checks},
        "timing": {k: _number(v) for k, v in _key(summary, "timings", folder).items()},
        "summary": summary,
    })


def _contact(pair: dict[str, Any], folder: Path) -> Contact:
    status = pair["status"]
    gap = _floats(pair["gap"])
    # JSON has no infinity: the gap of a point without a partner is written as null.
    gap[np.array([s == "no-partner" for s in status], dtype=bool)] = np.inf
    bodies = tuple(pair["bodies"])
    # A pair without friction has no friction keys: zeros and "open", as a solve gives.
    n = len(status)

    def friction_column(key: str) -> np.ndarray:
        return _floats(pair[key]) if key in pair else np.zeros(n)

    try:
        return Contact._from_state({
            "name": pair["name"],
            "bodies": bodies,
            "side": np.array([bodies.index(b) for b in pair["body"]], dtype=np.int64),
            "node": np.array(pair["node"], dtype=np.int64),
            "x": _floats(pair["x"]),
            "y": _floats(pair["y"]),
            "gap": gap,
            "pressure": _floats(pair["pressure"]),
            "nodal_traction": _floats(pair["nodal_traction"]),
            "closed": np.array([s == "closed" for s in status], dtype=bool),
            "status": list(status),
            "weight": _floats(pair["weight"]),
            "normal": _floats([c for n in pair["normal"] for c in n]).reshape(-1, 2),
            "nodal_force": _floats([c for f in pair["nodal_force"] for c in f]).reshape(-1, 2),
            "forces": tuple(tuple(_number(c) for c in f) for f in pair["force"]),
            "max_penetration": _number(pair["max_penetration"]),
            "complementarity": _number(pair["complementarity"]),
            "tangential": friction_column("tangential_traction"),
            "slip": friction_column("slip"),
            "total_slip": friction_column("total_slip"),
            "friction_status": list(pair.get("friction_status", ["open"] * n)),
            "tangential_force": _number(pair.get("tangential_force", 0.0)),
            "stick_length": _number(pair.get("stick_length", 0.0)),
            "slip_length": _number(pair.get("slip_length", 0.0)),
        })
    except (KeyError, ValueError, TypeError) as e:
        raise ContactddError(f"{folder}: summary.json: a contact pair not as contactdd writes it "
                             f"({type(e).__name__}: {e})") from e


def _history(path: Path, names: list[str]) -> dict[str, np.ndarray]:
    """``history.csv``: k, gamma, measure, then rel_change, active and normal_force per body."""
    try:
        lines = list(csv.reader(_read_text(path).splitlines()))
    except csv.Error as e:
        raise ContactddError(f"{path}: not a CSV file of contactdd: {e}") from e
    columns = ["k", "gamma", "measure"] + [f"{prefix}_{n}" for prefix in
                                           ("rel_change", "active", "normal_force") for n in names]
    if not lines or lines[0] != columns:
        raise ContactddError(f"{path}: expected the header {','.join(columns)}")
    rows = lines[1:]
    nb = len(names)
    if any(len(r) != len(columns) for r in rows):
        raise ContactddError(f"{path}: expected {len(columns)} columns for {nb} bodies")
    table = np.array([[float(v) for v in r] for r in rows], dtype=np.float64).reshape(-1, len(columns))
    counts = np.concatenate([table[:, :1], table[:, 3 + nb:3 + 2 * nb]], axis=1)
    if not np.all(np.isfinite(counts) & (counts == np.round(counts)) & (np.abs(counts) < 2**53)):
        raise ContactddError(f"{path}: the columns k and active_* must hold integers")
    return {
        "k": table[:, 0].astype(np.int64),
        "gamma": np.ascontiguousarray(table[:, 1]),
        "measure": np.ascontiguousarray(table[:, 2]),
        "rel_change": np.ascontiguousarray(table[:, 3:3 + nb]),
        "active": table[:, 3 + nb:3 + 2 * nb].astype(np.int64),
        "normal_force": np.ascontiguousarray(table[:, 3 + 2 * nb:]),
    }


def _result(summary: dict[str, Any], files: list[str], bodies: list[Body],
            contact: list[Contact], names: list[str], folder: Path) -> Result:
    if "history.csv" not in files:
        raise ContactddError(f"{folder}: summary.json lists no history.csv")
    steps = summary.get("steps")
    state = {
        key: _key(summary, key, folder)
        for key in ["converged", "stop", "iterations", "message", "method", "updates"]
    }
    gamma = _key(summary, "gamma", folder)
    state.update({
        "iteration": _key(summary, "iteration", folder),
        "solver": _key(summary, "solver", folder),
    })
    state.update({
        "gamma": gamma if gamma == "auto" else _number(gamma),
        "theta": [_number(t) for t in _key(summary, "theta", folder)],
        "gap_tol": summary.get("gap_tol"),
        "timing": {k: _number(v) for k, v in _key(summary, "timing_s", folder).items()},
        "history": _history(folder / "history.csv", names),
        "bodies": bodies,
        "contact": contact,
        "load_factor": _number(steps[-1]["factor"]) if steps else 1.0,
        "summary": summary,
    })
    return Result._from_state(state)


def _monolithic(summary: dict[str, Any], bodies: list[Body], contact: list[Contact],
                folder: Path) -> MonolithicResult:
    return MonolithicResult._from_state({
        "newton_steps": _key(summary, "newton_steps", folder),
        "rigid_modes": list(_key(summary, "rigid_modes", folder)),
        "bodies": bodies,
        "contact": contact,
        "seconds": _number(_key(summary, "timing_s", folder).get("total")),
        "summary": summary,
    })

#!/usr/bin/env python3
"""Writes the VTK XML cloud files the reader is tested on (tests/unit/io/test_vtk_cloud.cpp).

The same 12 points (3 x 4 lattice, z = 0, boundary tagged 1, one Neumann point with a normal)
and one field `k` in every encoding the VTK XML format has: ascii, inline base64 binary
(UInt32 and UInt64 headers, uncompressed and zlib-compressed in blocks), appended raw and
appended base64, as .vtu (UnstructuredGrid) and .vtp (PolyData). Only Python's standard
library: struct, base64, zlib. Run from this directory; the outputs are committed.
The vtk_written_* files were written once by VTK 9.1 itself (Debian python3-vtk9:
vtkXMLUnstructuredGridWriter / vtkXMLPolyDataWriter reading ascii.vtu, in appended zlib,
appended raw, binary and binary zlib modes); they are not regenerated here. So was
vtk_written_periodic.vtu: `vrsph cloud --family perturbed --n 8 --periodic x --output p.vtu
--vtu-format ascii` read and written again by VTK 9.1's vtkXMLUnstructuredGridWriter (its
default: appended raw, the field data vrsph_periodic_box / vrsph_periodic_axes included).
"""
import base64
import struct
import zlib

POINTS = [(0.25 * i, 0.5 * j, 0.0) for j in range(3) for i in range(4)]
TAGS = [0 if 0 < i < 3 and j == 1 else 1 for j in range(3) for i in range(4)]
TAGS[4] = 2  # (0, 0.5): Neumann, outward normal (-1, 0, 0)
NORMALS = [(-1.0, 0.0, 0.0) if t == 2 else (0.0, 0.0, 0.0) for t in TAGS]
K = [1.0 + x * x + 2 * y for x, y, _ in POINTS]


def arrays():
    pts = b"".join(struct.pack("<3d", *p) for p in POINTS)
    tag = b"".join(struct.pack("<i", t) for t in TAGS)
    nrm = b"".join(struct.pack("<3f", *n) for n in NORMALS)
    k = b"".join(struct.pack("<f", v) for v in K)
    return [("Points", "Float64", 3, pts), ("tag", "Int32", 1, tag), ("normals", "Float32", 3, nrm), ("K", "Float32", 1, k)]


def block_header(data, h64, compressed, block=40):
    w = "<Q" if h64 else "<I"
    if not compressed:
        return struct.pack(w, len(data)), data
    blocks = [data[i:i + block] for i in range(0, len(data), block)]
    comp = [zlib.compress(b) for b in blocks]
    last = len(blocks[-1]) if len(blocks[-1]) != block else 0
    head = struct.pack(w, len(blocks)) + struct.pack(w, block) + struct.pack(w, last)
    head += b"".join(struct.pack(w, len(c)) for c in comp)
    return head, b"".join(comp)


def write(name, kind, mode, h64=False, compressed=False):
    attrs = f'type="{kind}" version="1.0" byte_order="LittleEndian" header_type="{"UInt64" if h64 else "UInt32"}"'
    if compressed:
        attrs += ' compressor="vtkZLibDataCompressor"'
    appended = b""
    xml = {}
    for label, typ, comps, data in arrays():
        common = f'type="{typ}" NumberOfComponents="{comps}"' + ("" if label == "Points" else f' Name="{label}"')
        if mode == "ascii":
            fmt = "d" if typ == "Float64" else "f" if typ == "Float32" else "i"
            vals = struct.unpack("<" + fmt * (len(data) // struct.calcsize(fmt)), data)
            xml[label] = f'<DataArray {common} format="ascii">{" ".join(repr(v) for v in vals)}</DataArray>'
            continue
        head, body = block_header(data, h64, compressed)
        if mode == "binary":
            text = (base64.b64encode(head) + base64.b64encode(body)) if compressed else base64.b64encode(head + body)
            xml[label] = f'<DataArray {common} format="binary">{text.decode()}</DataArray>'
        else:
            enc = head + body if mode == "raw" else ((base64.b64encode(head) + base64.b64encode(body)) if compressed
                                                     else base64.b64encode(head + body))
            xml[label] = f'<DataArray {common} format="appended" offset="{len(appended)}"/>'
            appended += enc
    n = len(POINTS)
    cells = (f'<Cells><DataArray type="Int64" Name="connectivity" format="ascii">{" ".join(map(str, range(n)))}</DataArray>'
             f'<DataArray type="Int64" Name="offsets" format="ascii">{" ".join(map(str, range(1, n + 1)))}</DataArray>'
             f'<DataArray type="UInt8" Name="types" format="ascii">{" ".join(["1"] * n)}</DataArray></Cells>')
    if kind == "PolyData":
        piece_attr = f'NumberOfPoints="{n}" NumberOfVerts="{n}"'
        cells = cells.replace("<Cells>", "<Verts>").replace("</Cells>", "</Verts>").replace(
            '<DataArray type="UInt8" Name="types" format="ascii">' + " ".join(["1"] * n) + "</DataArray>", "")
    else:
        piece_attr = f'NumberOfPoints="{n}" NumberOfCells="{n}"'
    body = (f'<?xml version="1.0"?>\n<VTKFile {attrs}>\n<{kind}>\n<Piece {piece_attr}>\n<Points>{xml["Points"]}</Points>\n'
            f'{cells}\n<PointData Scalars="tag">{xml["tag"]}{xml["normals"]}{xml["K"]}</PointData>\n</Piece>\n</{kind}>\n')
    out = body.encode()
    if mode in ("raw", "base64"):
        out += f'<AppendedData encoding="{"raw" if mode == "raw" else "base64"}">\n_'.encode() + appended
        out += b"\n</AppendedData>\n"
    out += b"</VTKFile>\n"
    with open(name, "wb") as f:
        f.write(out)


write("ascii.vtu", "UnstructuredGrid", "ascii")
write("binary32.vtu", "UnstructuredGrid", "binary")
write("binary64_zlib.vtu", "UnstructuredGrid", "binary", h64=True, compressed=True)
write("appended_raw_zlib.vtu", "UnstructuredGrid", "raw", h64=True, compressed=True)
write("appended_raw.vtu", "UnstructuredGrid", "raw")
write("appended_base64.vtu", "UnstructuredGrid", "base64")
write("appended_base64_zlib.vtu", "UnstructuredGrid", "base64", compressed=True)
write("binary32.vtp", "PolyData", "binary")

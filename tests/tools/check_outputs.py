#!/usr/bin/env python3
"""Reads aggpack's output files with Python's own parsers, as a user's script would.

  check_outputs.py csv FILE [FILE ...]   every CSV loads as plain pandas.read_csv(FILE) would:
                                         the first line is the header, every row has its
                                         fields, and the cells are numbers (or ids, a
                                         figure's series names, or empty)
  check_outputs.py vtp FILE N [CSV] [--arrays A,B,..] [--contact-tolerance T]
                                         the VTP is well-formed XML with N points and every
                                         array of N tuples, decoded from ASCII or from
                                         VTK's zlib-compressed appended binary with zlib and
                                         struct (VTK's layout, not aggpack's code); the
                                         vertices are 0..N-1; with CSV (a particles.csv),
                                         the points, radii, diameters and ids equal its
                                         rows bit for bit; --arrays names point arrays that
                                         must be present; --contact-tolerance T checks the
                                         coordination array against contacts counted here
                                         from the CSV (|x_i - x_j| <= (r_i + r_j)(1 + T));
                                         --component-diameters D0,D1,.. checks that each
                                         sphere of component k has diameter Dk;
                                         --nonzero NAME: some value of NAME is not 0
  check_outputs.py vtp-same A B          two VTPs (say ASCII and binary) hold the same arrays,
                                         value for value
  check_outputs.py pvd FILE              the .pvd is a VTK Collection whose DataSets exist
                                         beside it, are valid VTPs (as above) and have
                                         strictly increasing timesteps; prints each
                                         "timestep file" line before "ok"

Prints what is wrong and exits 1; prints "ok" and exits 0 otherwise.
"""
import csv
import math
import os
import struct
import sys
import xml.etree.ElementTree as ET
import zlib

# VTK's word types as struct codes.
WORD_TYPES = {"Int8": "b", "UInt8": "B", "Int16": "h", "UInt16": "H", "Int32": "i", "UInt32": "I",
              "Int64": "q", "UInt64": "Q", "Float32": "f", "Float64": "d"}


def fail(message):
    print(message)
    sys.exit(1)


def is_number(text):
    try:
        float(text)
        return True
    except ValueError:
        return False


def check_csv(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if not rows:
        fail(f"{path}: empty")
    header = rows[0]
    if header[0].startswith("#"):
        fail(f"{path}: the first line is not a header but a comment: {header}")
    if any(not name or not name.replace("_", "").isalnum() for name in header):
        fail(f"{path}: header names must be plain identifiers: {header}")
    if len(set(header)) != len(header):
        fail(f"{path}: repeated column names: {header}")
    if len(rows) < 2:
        fail(f"{path}: no data rows")
    for number, row in enumerate(rows[1:], start=2):
        if len(row) != len(header):
            fail(f"{path}:{number}: {len(row)} fields for {len(header)} columns")
    # Each column holds one type, as a table reader types it: numbers (or empty), or words only
    # in a column whose name says so (supports.csv's support_k_kind, a figure's data its
    # series). A column mixing ids and words is read by pandas as strings or floats.
    for index, name in enumerate(header):
        words = name.endswith("_kind") or name == "series"
        for number, row in enumerate(rows[1:], start=2):
            cell = row[index]
            if words and name != "series" and not cell.replace("_", "").isalpha():
                fail(f"{path}:{number}: column {name}: '{cell}' is not a word")
            if not words and cell and not is_number(cell):
                fail(f"{path}:{number}: column {name}: '{cell}' is not a number")


def read_vtp(path):
    """The VTP's XML root and its point-related arrays, {name: [tuple or value, ...]}.

    The points are under "Points"; connectivity and offsets under their names. A file with
    <AppendedData encoding="raw"> holds raw bytes after the '_', which no XML parser takes:
    the XML is the text before that element, closed by hand, as VTK's reader splits it too.
    """
    data = open(path, "rb").read()
    marker = data.find(b"<AppendedData")
    appended = b""
    if marker >= 0:
        start = data.index(b"_", data.index(b">", marker)) + 1
        end = data.rindex(b"</AppendedData>")
        appended = data[start:end]
        text = data[:marker] + b"</VTKFile>\n"
    else:
        text = data
    root = ET.fromstring(text)  # raises on malformed XML, such as '--' inside a comment
    if root.tag != "VTKFile" or root.get("type") != "PolyData":
        fail(f"{path}: root is {root.tag} {root.attrib}, expected a PolyData VTKFile")
    order = {"LittleEndian": "<", "BigEndian": ">"}[root.get("byte_order", "LittleEndian")]
    header = {"UInt32": "I", "UInt64": "Q"}[root.get("header_type", "UInt32")]
    compressor = root.get("compressor")
    if compressor not in (None, "vtkZLibDataCompressor"):
        fail(f"{path}: compressor {compressor} is not VTK's zlib one")
    piece = root.find("PolyData/Piece")
    if piece is None:
        fail(f"{path}: no PolyData/Piece")
    arrays = {}
    for parent in piece:
        for array in parent.findall("DataArray"):
            name = array.get("Name") if parent.tag != "Points" else "Points"
            code = WORD_TYPES[array.get("type")]
            components = int(array.get("NumberOfComponents", "1"))
            form = array.get("format")
            if form == "ascii":
                cast = float if code in "fd" else int
                values = [cast(v) for v in (array.text or "").split()]
            elif form == "appended":
                if not compressor:
                    fail(f"{path}: {name}: appended data without the zlib compressor is not what aggpack writes")
                raw = decompress(path, name, appended, int(array.get("offset")), order + header)
                size = struct.calcsize(code)
                if len(raw) % size:
                    fail(f"{path}: {name}: {len(raw)} bytes are not whole {array.get('type')} words")
                values = list(struct.unpack(f"{order}{len(raw) // size}{code}", raw))
            else:
                fail(f"{path}: {name}: format {form!r}")
            if len(values) % components:
                fail(f"{path}: {name}: {len(values)} values are not whole tuples of {components}")
            arrays[name] = values if components == 1 else [tuple(values[i:i + components])
                                                           for i in range(0, len(values), components)]
    return root, piece, arrays


def decompress(path, name, appended, offset, word):
    """One array of VTK's compressed layout: [blocks, block size, last block size (0: full),
    each block's compressed size], then the blocks, each one zlib stream."""
    w = struct.calcsize(word)
    blocks, block_size, last_size = struct.unpack_from(word[0] + "3" + word[1], appended, offset)
    sizes = struct.unpack_from(word[0] + str(blocks) + word[1], appended, offset + 3 * w)
    at = offset + (3 + blocks) * w
    out = b""
    for b, size in enumerate(sizes):
        block = zlib.decompress(appended[at:at + size])
        expected = last_size if (b == blocks - 1 and last_size) else block_size
        if len(block) != expected:
            fail(f"{path}: {name}: block {b} inflates to {len(block)} bytes, the header says {expected}")
        out += block
        at += size
    return out


def check_vtp(path, count, particles_csv=None, required=(), contact_tolerance=None, component_diameters=None,
              nonzero=None):
    root, piece, arrays = read_vtp(path)
    if int(piece.get("NumberOfPoints")) != count or int(piece.get("NumberOfVerts")) != count:
        fail(f"{path}: expected {count} points and vertices, the Piece says {piece.attrib}")
    for name, values in arrays.items():
        if len(values) != count:
            fail(f"{path}: DataArray {name} has {len(values)} tuples for {count} points")
    if arrays.get("connectivity") != list(range(count)) or arrays.get("offsets") != list(range(1, count + 1)):
        fail(f"{path}: the vertices are not 0..N-1, one a cell")
    for name in required:
        if name not in arrays:
            fail(f"{path}: no point array {name}; it has {sorted(arrays)}")
    if nonzero and all(v in (0, (0, 0, 0)) for v in arrays[nonzero]):
        fail(f"{path}: every {nonzero} is 0")
    if component_diameters:
        for i, (k, d) in enumerate(zip(arrays["component"], arrays["diameter"])):
            if not 0 <= k < len(component_diameters) or not math.isclose(d, component_diameters[k], rel_tol=1e-12):
                fail(f"{path}: sphere {i} of component {k} has diameter {d}; expected {component_diameters}")
    if particles_csv:
        with open(particles_csv, newline="") as f:
            rows = list(csv.DictReader(f))
        if len(rows) != count:
            fail(f"{particles_csv}: {len(rows)} rows for {count} points")
        for i, row in enumerate(rows):
            point = (float(row["x"]), float(row["y"]), float(row["z"]))
            r = float(row["r"])
            got = (arrays["id"][i], arrays["Points"][i], arrays["radius"][i], arrays["diameter"][i])
            if got != (int(row["id"]), point, r, 2 * r):
                fail(f"{path}: point {i} is (id, xyz, radius, diameter) {got}; {particles_csv} says "
                     f"{(int(row['id']), point, r, 2 * r)}")
        if contact_tolerance is not None:
            expected = contact_counts(rows, contact_tolerance)
            for i, (k, got) in enumerate(zip(expected, arrays["coordination"])):
                if k != got:
                    fail(f"{path}: sphere {i} has coordination {got}; counted from {particles_csv}: {k}")
    return arrays


def contact_counts(rows, tolerance):
    """Each sphere's sphere-sphere contacts, by a cell grid of the largest diameter."""
    spheres = [(float(r["x"]), float(r["y"]), float(r["z"]), float(r["r"])) for r in rows]
    cell = 2 * max(s[3] for s in spheres) * (1 + tolerance)
    grid = {}
    for i, (x, y, z, _) in enumerate(spheres):
        grid.setdefault((math.floor(x / cell), math.floor(y / cell), math.floor(z / cell)), []).append(i)
    counts = [0] * len(spheres)
    for i, (x, y, z, r) in enumerate(spheres):
        cx, cy, cz = math.floor(x / cell), math.floor(y / cell), math.floor(z / cell)
        for dx in (-1, 0, 1):
            for dy in (-1, 0, 1):
                for dz in (-1, 0, 1):
                    for j in grid.get((cx + dx, cy + dy, cz + dz), ()):
                        xj, yj, zj, rj = spheres[j]
                        reach = (r + rj) * (1 + tolerance)
                        if j != i and (x - xj) ** 2 + (y - yj) ** 2 + (z - zj) ** 2 <= reach * reach:
                            counts[i] += 1
    return counts


def check_same_vtp(a, b):
    arrays_a, arrays_b = read_vtp(a)[2], read_vtp(b)[2]
    if sorted(arrays_a) != sorted(arrays_b):
        fail(f"{a} has arrays {sorted(arrays_a)}, {b} {sorted(arrays_b)}")
    for name in arrays_a:
        if arrays_a[name] != arrays_b[name]:
            first = next(i for i, (u, v) in enumerate(zip(arrays_a[name], arrays_b[name])) if u != v)
            fail(f"{name} differs at {first}: {arrays_a[name][first]} in {a}, {arrays_b[name][first]} in {b}")


def check_pvd(path):
    root = ET.parse(path).getroot()
    if root.tag != "VTKFile" or root.get("type") != "Collection":
        fail(f"{path}: root is {root.tag} {root.attrib}, expected a Collection VTKFile")
    datasets = root.findall("Collection/DataSet")
    if not datasets:
        fail(f"{path}: no DataSet")
    times = []
    for dataset in datasets:
        file = os.path.join(os.path.dirname(path), dataset.get("file"))
        if not os.path.isfile(file):
            fail(f"{path}: {dataset.get('file')} is not beside it")
        _, piece, _ = read_vtp(file)
        check_vtp(file, int(piece.get("NumberOfPoints")))
        times.append(float(dataset.get("timestep")))
        print(dataset.get("timestep"), dataset.get("file"))
    if any(b <= a for a, b in zip(times, times[1:])):
        fail(f"{path}: timesteps {times} do not increase")


def main(argv):
    if len(argv) >= 3 and argv[1] == "csv":
        for path in argv[2:]:
            check_csv(path)
    elif len(argv) >= 4 and argv[1] == "vtp":
        rest, options, args = [], {}, iter(argv[4:])
        for arg in args:
            if arg.startswith("--"):
                options[arg] = next(args)
            else:
                rest.append(arg)
        tolerance = options.get("--contact-tolerance")
        diameters = [float(d) for d in options.get("--component-diameters", "").split(",") if d]
        check_vtp(argv[2], int(argv[3]), rest[0] if rest else None,
                  [a for a in options.get("--arrays", "").split(",") if a],
                  float(tolerance) if tolerance is not None else None, diameters, options.get("--nonzero"))
    elif len(argv) == 4 and argv[1] == "vtp-same":
        check_same_vtp(argv[2], argv[3])
    elif len(argv) == 3 and argv[1] == "pvd":
        check_pvd(argv[2])
    else:
        fail(__doc__)
    print("ok")


if __name__ == "__main__":
    main(sys.argv)

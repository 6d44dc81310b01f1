#!/usr/bin/env python3
"""Reads aggpack's output files with Python's own parsers, as a user's script would.

  check_outputs.py csv FILE [FILE ...]   every CSV loads as plain pandas.read_csv(FILE) would:
                                         the first line is the header, every row has its
                                         fields, and the cells are numbers (or ids, or empty)
  check_outputs.py vtp FILE N            the VTP is well-formed XML with N points and every
                                         point array of N values

Prints what is wrong and exits 1; prints "ok" and exits 0 otherwise.
"""
import csv
import sys
import xml.etree.ElementTree as ET


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
    # in a column whose name says so (supports.csv's support_k_kind). A column mixing ids and
    # words is read by pandas as strings or floats.
    for index, name in enumerate(header):
        words = name.endswith("_kind")
        for number, row in enumerate(rows[1:], start=2):
            cell = row[index]
            if words and not cell.replace("_", "").isalpha():
                fail(f"{path}:{number}: column {name}: '{cell}' is not a word")
            if not words and cell and not is_number(cell):
                fail(f"{path}:{number}: column {name}: '{cell}' is not a number")


def check_vtp(path, count):
    root = ET.parse(path).getroot()  # raises on malformed XML, such as '--' inside a comment
    if root.tag != "VTKFile" or root.get("type") != "PolyData":
        fail(f"{path}: root is {root.tag} {root.attrib}, expected a PolyData VTKFile")
    piece = root.find("PolyData/Piece")
    if piece is None or int(piece.get("NumberOfPoints")) != count:
        fail(f"{path}: expected {count} points, the Piece says {None if piece is None else piece.get('NumberOfPoints')}")
    for array in piece.iter("DataArray"):
        values = array.text.split() if array.text else []
        components = int(array.get("NumberOfComponents", "1"))
        if len(values) != count * components:
            fail(f"{path}: DataArray {array.get('Name')} has {len(values)} values for {count} points")


def main(argv):
    if len(argv) >= 3 and argv[1] == "csv":
        for path in argv[2:]:
            check_csv(path)
    elif len(argv) == 4 and argv[1] == "vtp":
        check_vtp(argv[2], int(argv[3]))
    else:
        fail(__doc__)
    print("ok")


if __name__ == "__main__":
    main(sys.argv)

#!/usr/bin/python3
"""Independent check of a snapshot directory written by polydem's SnapshotWriter.

Reads DIR/snapshots.pvd and DIR/contacts.pvd with Python's own XML parser and base64 decoder and
checks what ParaView relies on: every referenced file exists and parses, the parallel headers
declare exactly the arrays of the pieces, array lengths match the point and cell counts, offsets
and connectivity are consistent, and every particle is a closed polygon mesh with outward faces
(each edge used once in each direction, positive volume). Exit status 0 when all holds.

Usage: /usr/bin/python3 check_vtk_files.py DIR
"""
import base64
import math
import os
import struct
import sys
import xml.etree.ElementTree as ET

TYPES = {"Float64": "d", "Int64": "q", "UInt64": "Q", "Int32": "i", "UInt8": "B"}


def fail(message):
    print("check_vtk_files: " + message, file=sys.stderr)
    sys.exit(1)


def decode(array, root, appended):
    kind = TYPES[array.get("type")]
    order = "<" if root.get("byte_order") == "LittleEndian" else ">"
    if array.get("format") == "ascii":
        cast = float if kind == "d" else int
        return [cast(v) for v in array.text.split()]
    if root.get("header_type") != "UInt64":
        fail("header_type is not UInt64")
    offset = int(array.get("offset"))
    head = base64.b64decode(appended[offset:offset + 12])
    (nbytes,) = struct.unpack(order + "Q", head[:8])
    chars = 4 * ((8 + nbytes + 2) // 3)
    block = base64.b64decode(appended[offset:offset + chars], validate=True)
    size = struct.calcsize(kind)
    if len(block) != 8 + nbytes or nbytes % size:
        fail("bad appended block for " + array.get("Name"))
    return list(struct.unpack(order + kind * (nbytes // size), block[8:]))


def read_piece(path):
    with open(path, "rb") as f:
        text = f.read().decode("ascii")
    root = ET.fromstring(text)
    if root.tag != "VTKFile" or root.get("type") != "PolyData":
        fail(path + ": not a PolyData file")
    appended = ""
    data = root.find("AppendedData")
    if data is not None:
        if data.get("encoding") != "base64":
            fail(path + ": appended data not base64")
        appended = data.text.strip()
        if not appended.startswith("_"):
            fail(path + ": appended data does not start with '_'")
        appended = appended[1:]
    piece = root.find("PolyData/Piece")
    counts = {k: int(piece.get("NumberOf" + k)) for k in ("Points", "Verts", "Polys")}
    arrays = {}
    for section in piece:
        for array in section.findall("DataArray"):
            key = array.get("Name")
            if section.tag in ("Verts", "Polys"):
                key = section.tag + "/" + key
            arrays[key] = (section.tag, array, decode(array, root, appended))
    return counts, arrays


def check_topology(path, counts, arrays, cells):
    conn = arrays[cells + "/connectivity"][2]
    offs = arrays[cells + "/offsets"][2]
    if len(offs) != counts[cells]:
        fail(path + ": %d offsets for %d %s" % (len(offs), counts[cells], cells))
    previous = 0
    for o in offs:
        if o <= previous:
            fail(path + ": offsets not increasing")
        previous = o
    if offs and offs[-1] != len(conn):
        fail(path + ": last offset %d, connectivity %d" % (offs[-1], len(conn)))
    if any(i < 0 or i >= counts["Points"] for i in conn):
        fail(path + ": connectivity index out of range")
    return conn, offs


def check_particles(path, counts, arrays):
    conn, offs = check_topology(path, counts, arrays, "Polys")
    points = arrays["Points"][2]
    uid = arrays["uid"][2]
    for name, (section, array, values) in arrays.items():
        if section in ("CellData",):
            n = int(array.get("NumberOfComponents"))
            if len(values) != n * counts["Polys"]:
                fail(path + ": cell array %s has %d values" % (name, len(values)))
    if len(points) != 3 * counts["Points"]:
        fail(path + ": %d point coordinates" % len(points))
    velocity, speed = arrays["velocity"][2], arrays["speed"][2]
    for c in range(counts["Polys"]):
        v = velocity[3 * c:3 * c + 3]
        if abs(math.sqrt(sum(x * x for x in v)) - speed[c]) > 1e-15 * max(1.0, speed[c]):
            fail(path + ": speed is not |velocity| on cell %d" % c)
    # Group faces by particle and check each is a closed, outward-oriented surface.
    faces = {}
    start = 0
    for c, end in enumerate(offs):
        faces.setdefault(uid[c], []).append(conn[start:end])
        start = end
    for particle, polygons in faces.items():
        edges = {}
        volume = 0.0
        for poly in polygons:
            for k in range(len(poly)):
                a, b = poly[k], poly[(k + 1) % len(poly)]
                edges[(a, b)] = edges.get((a, b), 0) + 1
            p0 = points[3 * poly[0]:3 * poly[0] + 3]
            for k in range(1, len(poly) - 1):
                p1 = points[3 * poly[k]:3 * poly[k] + 3]
                p2 = points[3 * poly[k + 1]:3 * poly[k + 1] + 3]
                volume += (p0[0] * (p1[1] * p2[2] - p1[2] * p2[1])
                           - p0[1] * (p1[0] * p2[2] - p1[2] * p2[0])
                           + p0[2] * (p1[0] * p2[1] - p1[1] * p2[0])) / 6.0
        for (a, b), n in edges.items():
            if n != 1 or edges.get((b, a)) != 1:
                fail(path + ": particle %d is not a closed outward surface" % particle)
        if volume <= 0:
            fail(path + ": particle %d has volume %g" % (particle, volume))
    return len(faces)


def check_contacts(path, counts, arrays):
    conn, offs = check_topology(path, counts, arrays, "Verts")
    if conn != list(range(counts["Points"])):
        fail(path + ": contact vertices do not list the points in order")
    for name, (section, array, values) in arrays.items():
        if section == "PointData":
            if len(values) != int(array.get("NumberOfComponents")) * counts["Points"]:
                fail(path + ": point array %s has %d values" % (name, len(values)))
    return counts["Points"]


def check_collection(run_dir, name, check_piece):
    pvd = os.path.join(run_dir, name)
    root = ET.parse(pvd).getroot()
    if root.get("type") != "Collection":
        fail(pvd + ": not a Collection")
    times, total = [], 0
    for dataset in root.iter("DataSet"):
        times.append(float(dataset.get("timestep")))
        pvtp = os.path.join(run_dir, dataset.get("file"))
        header = ET.parse(pvtp).getroot()
        if header.get("type") != "PPolyData":
            fail(pvtp + ": not PPolyData")
        declared = {a.get("Name"): (a.get("type"), a.get("NumberOfComponents"))
                    for a in header.iter("PDataArray")}
        sources = [p.get("Source") for p in header.iter("Piece")]
        if not sources:
            fail(pvtp + ": no pieces")
        for source in sources:
            path = os.path.join(os.path.dirname(pvtp), source)
            counts, arrays = read_piece(path)
            found = {k: (a.get("type"), a.get("NumberOfComponents"))
                     for k, (section, a, v) in arrays.items() if "/" not in k}
            if found != declared:
                fail(path + ": arrays differ from those declared in " + pvtp)
            total += check_piece(path, counts, arrays)
    if times != sorted(times) or len(set(times)) != len(times):
        fail(pvd + ": times not strictly increasing")
    return len(times), total


def main():
    if len(sys.argv) != 2:
        fail("usage: check_vtk_files.py DIR")
    run_dir = sys.argv[1]
    snapshots, particles = check_collection(run_dir, "snapshots.pvd", check_particles)
    contact_sets, contacts = check_collection(run_dir, "contacts.pvd", check_contacts)
    if snapshots == 0:
        fail("no snapshots")
    print("ok: %d snapshots (%d particle records), %d contact sets (%d contacts)"
          % (snapshots, particles, contact_sets, contacts))


if __name__ == "__main__":
    main()

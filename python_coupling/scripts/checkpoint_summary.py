#!/usr/bin/python3
"""Summary of a polydem checkpoint file, with every dataset's checksum verified.

Usage: /usr/bin/python3 checkpoint_summary.py FILE [--json OUT] [--quiet]

Prints the step, time, stage, particle and pair counts, the bounding box of the particle
centroids, the kinetic energy of the free particles and every dataset with its checksum.
--json OUT also writes the summary as JSON (OUT = "-" for standard output, then the text goes
to standard error). Exit status: 0 if the file is a valid checkpoint whose checksums and
whole-file digest all match, 1 if not (the problems are listed), 2 for a usage error or without
h5py. Format version 1 and 2 files (no digest, written before it existed) are summarised with
their checksums verified and a warning that edits of attributes and mixed datasets go
undetected; polydem restarts from them with the same warning (docs/checkpoint.md, "Older
files").

Needs h5py and numpy (Debian: python3-h5py). The checksum ("polydem-sum64", docs/checkpoint.md)
of a dataset of E elements u_0 .. u_{E-1} (row-major order; each element's little-endian bit
pattern read as an unsigned integer and zero-extended to 64 bits; strings byte by byte,
including their NUL padding) is

    mix64((sum_j mix64(u_j + (j + 1) * 0x9e3779b97f4a7c15)) xor E)     (all mod 2^64)

where mix64 is the SplitMix64 finaliser. The whole-file digest (version 3) is the same sum over
the bytes of a walk of every group, dataset, link and attribute (docs/checkpoint.md, "Digest";
module/hdf5/file_digest.h). Both are computed here independently of the C++ code.
"""

import argparse
import json
import sys

try:
    import h5py
    import numpy as np
except ImportError as e:  # pragma: no cover - reported to the user
    sys.stderr.write("checkpoint_summary.py needs h5py and numpy (Debian: python3-h5py): %s\n" % e)
    sys.exit(2)

FORMAT = "polydem-checkpoint"
FORMAT_VERSION = 6
READABLE_VERSIONS = (1, 2, 3, 4, 5, 6)  # 1: no sub-contacts; 1 and 2: no whole-file digest;
#                                   before 4: no joint planes; before 5: no joint-law history;
#                                   before 6: no bolts
DIGEST_VERSION = 3
MASK = (1 << 64) - 1
GAMMA = 0x9E3779B97F4A7C15
CHUNK = 1 << 20  # elements hashed per numpy pass

# Every dataset a version-1 checkpoint holds; versions 2 on add REQUIRED_V2, 4 on REQUIRED_V4,
# 5 on REQUIRED_V5.
REQUIRED = [
    "/run/state", "/scene/toml",
    "/shapes/name", "/shapes/vertex_offset", "/shapes/vertices", "/shapes/face_offset",
    "/shapes/face_vertex_offset", "/shapes/face_vertices", "/shapes/volume",
    "/shapes/principal_moments", "/shapes/circumradius", "/shapes/inradius",
    "/materials/name", "/materials/density", "/materials/kn", "/materials/ks",
    "/materials/friction_angle", "/materials/cohesion", "/materials/normal_damping",
    "/materials/local_damping", "/materials/penalty",
    "/materials/interaction/pair", "/materials/interaction/kn", "/materials/interaction/ks",
    "/materials/interaction/friction_angle", "/materials/interaction/cohesion",
    "/materials/interaction/normal_damping", "/materials/interaction/penalty",
    "/domain/lo", "/domain/hi", "/domain/blocks", "/domain/periodic", "/domain/rank_map",
    "/particles/uid", "/particles/shape", "/particles/material", "/particles/flags",
    "/particles/driver", "/particles/position", "/particles/orientation", "/particles/velocity",
    "/particles/angular_momentum",
    "/contacts/pair", "/contacts/shear_force", "/contacts/normal", "/contacts/warm_direction",
    "/contacts/warm_point", "/contacts/warm_valid", "/contacts/kernel_reserved",
    "/contacts/touching",
]
REQUIRED_V2 = [
    "/materials/jkn", "/materials/jks", "/materials/interaction/jkn",
    "/materials/interaction/jks",
    "/subcontacts/pair", "/subcontacts/feature", "/subcontacts/shear_force",
    "/subcontacts/normal",
]
REQUIRED_V4 = ["/shapes/face_plane"]
REQUIRED_V5 = ["/subcontacts/law_state"]
REQUIRED_V6 = ["/bolts/axial_plastic", "/bolts/shear_plastic", "/bolts/broken"]

FIXED, DRIVEN = 1 << 1, 1 << 2


def mix64_array(z):
    """SplitMix64 finaliser on a uint64 array (numpy arrays wrap silently mod 2^64)."""
    z = (z ^ (z >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
    z = (z ^ (z >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)
    return z ^ (z >> np.uint64(31))


def mix64(z):
    """SplitMix64 finaliser on a Python integer."""
    z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & MASK
    z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & MASK
    return z ^ (z >> 31)


def partial_sum(elements, first_index):
    """Sum over t_j of a slice of elements (uint64 array) starting at element first_index."""
    total = 0
    for start in range(0, len(elements), CHUNK):
        chunk = elements[start:start + CHUNK]
        j = np.arange(first_index + start + 1, first_index + start + 1 + len(chunk),
                      dtype=np.uint64)
        terms = mix64_array(chunk + j * np.uint64(GAMMA))
        total = (total + int(terms.sum(dtype=np.uint64))) & MASK
    return total


def as_elements(array):
    """The elements of a numeric or fixed-length string array as zero-extended uint64 bits."""
    a = np.ascontiguousarray(array)
    if a.dtype.kind == "S":
        return np.frombuffer(a.tobytes(), dtype=np.uint8).astype(np.uint64)
    unsigned = a.reshape(-1).view("<u%d" % a.dtype.itemsize)
    return unsigned.astype(np.uint64)


def dataset_checksum(ds):
    """The checksum of a dataset, read in slices of rows."""
    if ds.shape == ():  # a scalar fixed-length string: its bytes with their NUL padding
        raw = bytes(ds[()]).ljust(ds.dtype.itemsize, b"\0")
        elements = np.frombuffer(raw, dtype=np.uint8).astype(np.uint64)
        return mix64(partial_sum(elements, 0) ^ len(elements))
    rows = ds.shape[0]
    per_row = int(np.prod(ds.shape[1:], dtype=np.int64)) if len(ds.shape) > 1 else 1
    if ds.dtype.kind == "S":
        per_row *= ds.dtype.itemsize
    step = max(1, CHUNK // max(per_row, 1))
    total = 0
    for begin in range(0, rows, step):
        part = as_elements(ds[begin:min(rows, begin + step)])
        total = (total + partial_sum(part, begin * per_row)) & MASK
    return mix64(total ^ (rows * per_row))


def type_name(tid):
    """The digest's name of an HDF5 type: f8, i4, u1, s12, v... (module/hdf5/file_digest.h)."""
    cls = tid.get_class()
    order = "be" if cls in (h5py.h5t.INTEGER, h5py.h5t.FLOAT) and \
        tid.get_order() == h5py.h5t.ORDER_BE else ""
    if cls == h5py.h5t.INTEGER:
        sign = "u" if tid.get_sign() == h5py.h5t.SGN_NONE else "i"
        return "%s%d%s" % (sign, tid.get_size(), order)
    if cls == h5py.h5t.FLOAT:
        return "f%d%s" % (tid.get_size(), order)
    if cls == h5py.h5t.STRING:
        return "v" if tid.is_variable_str() else "s%d" % tid.get_size()
    return "c%d" % cls


def digest_walk(f):
    """The byte string the whole-file digest hashes, and the datasets' paths in walk order."""
    out = bytearray()
    datasets = []

    def text(value):
        out.extend(value if isinstance(value, bytes) else value.encode())
        out.append(0)

    def attributes(obj, path):
        for name in sorted(n.encode() for n in obj.attrs.keys()):
            if path == "/" and name == b"digest":
                continue
            aid = h5py.h5a.open(obj.id, name)
            tname = type_name(aid.get_type())
            count = aid.get_space().get_simple_extent_npoints()
            out.extend(b"A")
            text(name)
            text(tname)
            text(str(count))
            if count > 0 and tname[0] in "iufs":
                values = np.empty(aid.shape, dtype=aid.dtype)
                aid.read(values)
                if tname[0] != "s":  # numbers in native (little-endian) order
                    values = values.astype(values.dtype.newbyteorder("<"))
                out.extend(values.tobytes())

    def visit(path, obj):
        if isinstance(obj, h5py.Group):
            out.extend(b"G")
            text(path)
            attributes(obj, path)
            for name in sorted(n.encode() for n in obj.keys()):
                child = ("/" if path == "/" else path + "/") + name.decode()
                link = obj.get(name.decode(), getlink=True)
                if isinstance(link, h5py.HardLink):
                    visit(child, obj[name.decode()])
                elif isinstance(link, h5py.SoftLink):
                    out.extend(b"S")
                    text(child)
                    text(link.path)
                else:
                    out.extend(b"E")
                    text(child)
        elif isinstance(obj, h5py.Dataset):
            out.extend(b"D")
            text(path)
            text(type_name(obj.id.get_type()))
            text(",".join(str(d) for d in (obj.shape or ())))
            attributes(obj, path)
            datasets.append(path)
        else:
            out.extend(b"O")
            text(path)

    visit("/", f)
    return bytes(out), datasets


def bytes_checksum(data):
    """polydem-sum64 of a byte string (each byte one element)."""
    elements = np.frombuffer(data, dtype=np.uint8).astype(np.uint64)
    return mix64(partial_sum(elements, 0) ^ len(elements))


def text_of(ds):
    return bytes(ds[()]).ljust(ds.dtype.itemsize, b"\0")[: int(ds.attrs["length"])]


def attr_str(value):
    return value.decode() if isinstance(value, (bytes, np.bytes_)) else str(value)


def rotate_inverse(q, v):
    """R(q)^T v for unit quaternions q (rows w, x, y, z) and vectors v (rows x, y, z)."""
    w, u = q[:, :1], -q[:, 1:]
    t = 2.0 * np.cross(u, v)
    return v + w * t + np.cross(u, t)


def summarize(path):
    problems = []
    datasets = {}
    with h5py.File(path, "r") as f:
        fmt = attr_str(f.attrs.get("format", b""))
        version = int(f.attrs.get("format_version", -1))
        if fmt != FORMAT:
            problems.append("not a polydem checkpoint (format attribute is %r)" % fmt)
        elif version not in READABLE_VERSIONS:
            problems.append("format version %d; this script reads versions %s"
                            % (version, ", ".join(str(v) for v in READABLE_VERSIONS)))
        if problems:
            return {"file": path, "ok": False, "problems": problems}
        stream, walked = digest_walk(f)
        computed_digest = bytes_checksum(stream)
        stored_digest = int(f.attrs["digest"]) if "digest" in f.attrs else None
        if version >= DIGEST_VERSION and stored_digest != computed_digest:
            problems.append("the file was changed after it was written: its whole-file digest "
                            "is %s but its groups, datasets and attributes hash to %016x"
                            % ("missing" if stored_digest is None else "%016x" % stored_digest,
                               computed_digest))
        required = REQUIRED + (REQUIRED_V2 if version >= 2 else []) + \
            (REQUIRED_V4 if version >= 4 else []) + (REQUIRED_V5 if version >= 5 else []) + \
            (REQUIRED_V6 if version >= 6 else [])
        for name in required:
            if name not in f:
                problems.append("dataset %s is missing" % name)
        for name in walked:
            if name not in required:
                problems.append("dataset %s is not part of a version %d checkpoint"
                                % (name, version))
        if any(p.startswith("dataset ") and p.endswith("missing") for p in problems):
            return {"file": path, "ok": False, "problems": problems}

        def visit(name, obj):
            if isinstance(obj, h5py.Dataset):
                name = "/" + name
                stored = int(obj.attrs["checksum"]) if "checksum" in obj.attrs else None
                computed = dataset_checksum(obj)
                ok = stored == computed
                if not ok:
                    problems.append("dataset %s is corrupted: its checksum is %s but its data "
                                    "hash to %016x" % (name, "missing" if stored is None
                                                       else "%016x" % stored, computed))
                datasets[name] = {"shape": list(obj.shape), "checksum": "%016x" % computed,
                                  "ok": ok}
        f.visititems(visit)

        run = f["run"].attrs
        scene_text = text_of(f["scene/toml"])
        scene_hash = int(f["scene"].attrs["hash"])
        computed_scene = mix64(partial_sum(np.frombuffer(scene_text, dtype=np.uint8)
                                           .astype(np.uint64), 0) ^ len(scene_text))
        if computed_scene != scene_hash:
            problems.append("/scene: the scene text does not match its hash")

        replicated = int(f["particles"].attrs["replicated_count"])
        position = f["particles/position"][()]
        flags = f["particles/flags"][()]
        free = np.arange(len(flags)) >= replicated
        if np.any(((flags & (FIXED | DRIVEN)) != 0) == free):
            problems.append("/particles: replicated rows and flags disagree")
        shape = f["particles/shape"][()][free]
        material = f["particles/material"][()][free]
        velocity = f["particles/velocity"][()][free]
        momentum = f["particles/angular_momentum"][()][free]
        orientation = f["particles/orientation"][()][free]
        density = f["materials/density"][()][material]
        volume = f["shapes/volume"][()][shape]
        moments = f["shapes/principal_moments"][()][shape] * density[:, None]
        body_l = rotate_inverse(orientation, momentum)
        energy = float(np.sum(0.5 * density * volume * np.sum(velocity ** 2, axis=1))
                       + np.sum(0.5 * np.sum(body_l ** 2 / moments, axis=1)))
        touching = int(np.count_nonzero(f["contacts/touching"][()]))

        summary = {
            "file": path,
            "ok": not problems,
            "problems": problems,
            "format_version": version,
            "digest": "%016x" % computed_digest if version >= DIGEST_VERSION else None,
            "code_version": attr_str(f.attrs["code_version"]),
            "writer_ranks": int(f.attrs["writer_ranks"]),
            "scene_file": attr_str(f["scene"].attrs["file_name"]),
            "scene_hash": "%016x" % scene_hash,
            "step": int(run["step"]),
            "time": float(run["time"]),
            "dt": float(run["dt"]),
            "stage": attr_str(run["stage_name"]),
            "equilibrium_steps": int(run["equilibrium_steps"]),
            "equilibrium_reached": bool(run["equilibrium_reached"]),
            "particles": int(len(flags)),
            "replicated_particles": replicated,
            "pairs": int(f["contacts/pair"].shape[0]),
            "touching_pairs": touching,
            "shapes": int(f["shapes/name"].shape[0]),
            "materials": int(f["materials/name"].shape[0]),
            "domain_lo": [float(x) for x in f["domain/lo"][()]],
            "domain_hi": [float(x) for x in f["domain/hi"][()]],
            "particles_lo": [float(x) for x in position.min(axis=0)] if len(position) else None,
            "particles_hi": [float(x) for x in position.max(axis=0)] if len(position) else None,
            "kinetic_energy": energy,
            "datasets": datasets,
        }
    return summary


def text(summary):
    if "step" not in summary:
        return "file: %s\nINVALID:\n  %s\n" % (summary["file"], "\n  ".join(summary["problems"]))
    s = summary
    lines = [
        "file: %s" % s["file"],
        "format version: %d" % s["format_version"],
        ("digest: %s (whole file, %s)" % (s["digest"], "verified" if s["ok"] else "see below"))
        if s["digest"] else "digest: none (format version %d: edits of attributes and datasets "
        "mixed from other checkpoints are not detected)" % s["format_version"],
        "written by: polydem %s on %d ranks" % (s["code_version"], s["writer_ranks"]),
        "scene: %s (hash %s)" % (s["scene_file"], s["scene_hash"]),
        "step: %d" % s["step"],
        "time: %r s" % s["time"],
        "dt: %r s" % s["dt"],
        "stage: %s (equilibrium steps %d, %s)" % (s["stage"], s["equilibrium_steps"],
                                                  "reached" if s["equilibrium_reached"]
                                                  else "not reached"),
        "particles: %d (%d fixed or driven)" % (s["particles"], s["replicated_particles"]),
        "pair histories: %d (%d touching)" % (s["pairs"], s["touching_pairs"]),
        "shapes: %d, materials: %d" % (s["shapes"], s["materials"]),
        "domain: %s - %s m" % (s["domain_lo"], s["domain_hi"]),
        "particle centroids: %s - %s m" % (s["particles_lo"], s["particles_hi"]),
        "kinetic energy (free particles, velocities at t - dt/2): %r J" % s["kinetic_energy"],
        "datasets (%d):" % len(s["datasets"]),
    ]
    for name in sorted(s["datasets"]):
        d = s["datasets"][name]
        dims = " x ".join(str(x) for x in d["shape"]) or "scalar"
        lines.append("  %s [%s] %s %s" % (name, dims, d["checksum"],
                                          "ok" if d["ok"] else "CORRUPTED"))
    lines.append("checksums: %s" % ("all verified" if s["ok"] else "FAILED"))
    for p in s["problems"]:
        lines.append("problem: %s" % p)
    return "\n".join(lines) + "\n"


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("file")
    parser.add_argument("--json", metavar="OUT", help="also write JSON (- for stdout)")
    parser.add_argument("--quiet", action="store_true", help="no text summary")
    args = parser.parse_args(argv)
    try:
        summary = summarize(args.file)
    except (OSError, KeyError) as e:
        summary = {"file": args.file, "ok": False, "problems": ["unreadable: %s" % e]}
    out = sys.stderr if args.json == "-" else sys.stdout
    if not args.quiet:
        out.write(text(summary))
    if args.json:
        payload = json.dumps(summary, indent=1)
        if args.json == "-":
            sys.stdout.write(payload + "\n")
        else:
            with open(args.json, "w") as f:
                f.write(payload + "\n")
    return 0 if summary["ok"] else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

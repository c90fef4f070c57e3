"""Scene.load and Scene.from_toml: a scene file read into a polydem.Scene, to change and extend in
Python. The values are kept as the file writes them (strings with units included); the scene
reader checks them when the scene is built, as it checks the file.
"""
import os
import re
import tomllib

_TABLES = ("material", "interaction", "joint", "shape", "driver", "check", "bolt")
_BODIES = ("particle", "particle_grid", "rock_mass")
_BODY_HEADER = re.compile(r"^\s*\[\[\s*(particle|particle_grid|rock_mass)\s*\]\]\s*(#.*)?$")


def body_order(text):
    """The kinds of the [[particle]], [[particle_grid]] and [[rock_mass]] headers of `text`, in
    file order: the order that gives the bodies their uids, which tomllib's lists lose."""
    return [m.group(1) for m in map(_BODY_HEADER.match, text.splitlines()) if m]


def _resolve_records(scene, name):
    """A [seismic] record named relative to the scene file (as the reader resolves it) becomes
    an absolute path, so that the loaded scene finds it wherever it is written or built."""
    seismic = scene._sections.get("seismic")
    if not isinstance(seismic, dict) or name.startswith("<"):
        return
    folder = os.path.dirname(os.path.abspath(name))
    for key in ("record", "record_x", "record_y", "record_z"):
        if isinstance(seismic.get(key), str) and not os.path.isabs(seismic[key]):
            seismic[key] = os.path.join(folder, seismic[key])


def fill(scene, text, name):
    """Fills the empty polydem.Scene `scene` from scene-file text (what the file says, as
    tomllib reads it); ValueError for text that is not TOML."""
    try:
        doc = tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        raise ValueError("%s: not TOML: %s" % (name, e)) from None
    lists = {kind: list(doc.get(kind, [])) for kind in _BODIES}
    order = body_order(text)
    if sorted(order) != sorted(k for k in _BODIES for _ in lists[k]):
        # Bodies written as inline arrays (particle = [{...}]) have no header to order them by.
        raise ValueError("%s: give each [[particle]], [[particle_grid]] and [[rock_mass]] as a "
                         "[[...]] table of its own to load the scene into polydem.Scene" % name)
    for key, value in doc.items():
        # [[random]] and [realizations] are a study's (`polydem fos --realizations`); a Scene is
        # one scene, with the file's own values, as polydem's reader reads it.
        if key in _BODIES or key in ("random", "realizations"):
            continue
        if key == "scene" and isinstance(value, dict):
            scene._scene = dict(value)
        elif key == "simulation" and isinstance(value, dict):
            scene._simulation = dict(value)
        elif key in _TABLES and isinstance(value, list):
            scene._entries[key] = [dict(e) for e in value]
        else:
            scene._sections[key] = value  # the reader judges it when the scene is built
    scene._bodies = [(kind, dict(lists[kind].pop(0))) for kind in order]
    _resolve_records(scene, name)
    # uids: one per particle, count[0] count[1] count[2] per grid, and a rock mass's blocks,
    # which only cutting it tells (the built scene's rock_masses, in file order).
    built = scene.build()
    blocks = iter(r["blocks"] for r in built.rock_masses)
    uid = 1
    for kind, body in scene._bodies:
        if kind == "particle":
            scene._particle_uids[uid] = body
            uid += 1
        elif kind == "particle_grid":
            n = body["count"]
            uid += int(n[0]) * int(n[1]) * int(n[2])
        else:
            uid += next(blocks)
    scene._next_uid = uid
    return scene

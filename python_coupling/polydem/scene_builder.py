"""polydem.Scene: a whole scene built in Python, without a scene file.

The builder writes the scene as the TOML of docs/scene-format.md (to_toml(), save()) and builds
it with polydem's own scene reader (build()), so a scene built here and the same scene run from
its file by `polydem run` are the same run, bit for bit, and a checkpoint of its run stores that
text and can be continued (Simulation.restart). Arguments are checked as they are given (TypeError,
ValueError naming the method and the value); the reader checks the rest when the scene is built.
"""
import os

from . import _scene_load
from . import _toml
from . import _values as v
from ._polydem import InputError, parse_scene
from ._scene_bodies import Bodies

_SIMULATION_KEYS = ("kernel", "broadphase", "contact_model", "contact_point", "dt", "end_time",
                    "steps", "gravity", "contact_margin")
_SECTION_KEYS = {
    "kernel_params": ("lp_rounding",),
    "domain": ("min", "max", "blocks", "periodic", "rebalance_every", "balancer", "sort_every"),
    "equilibrium": ("enabled", "local_damping", "friction_angle", "force_ratio", "max_steps",
                    "reset_velocities"),
    "output": ("series_every", "snapshot_every", "progress_every", "monitor"),
    "checkpoint": ("every_steps", "every_seconds", "keep"),
    "fos": ("interactions", "f_min", "f_max", "resolution", "max_time", "time_cap",
            "settle_time", "force_ratio", "speed_decay", "local_damping", "speed_limit",
            "displacement_limit", "check_every", "label_prefix", "reduce_bolts"),
    "water": ("unit_weight", "level", "points", "table", "joint"),
    "seismic": ("kh", "azimuth", "kv", "record", "record_x", "record_y", "record_z", "time_step",
                "units", "scale"),
}
_RECORD_KEYS = ("record", "record_x", "record_y", "record_z")
_CONTACT_KEYS = ("kn", "ks", "friction_angle", "cohesion", "normal_damping", "penalty", "jkn",
                 "jks")
_SHAPE_TYPES = ("box", "vertices", "prism", "triangular_prism", "pyramid", "tetrahedron", "cube",
                "octahedron", "dodecahedron", "icosahedron", "hexagonal_prism", "random")
_VECTOR_KEYS = ("gravity", "min", "max", "size", "velocity", "angular_velocity", "pivot",
                "oscillation", "position", "origin", "point", "direction")


def _entry_value(key, value, where):
    """A value of a generic key: vectors by name, counts and flags as they are, numbers checked."""
    if key in _VECTOR_KEYS:
        return v.vec3(value, where)
    if key == "rotation":
        return v.rotation(value, where)
    if isinstance(value, (bool, str)) or value is None:
        return value
    if isinstance(value, int):
        return value  # counts (series_every, keep, check_every, seed...)
    if isinstance(value, dict):
        return v.table(value, where)
    if isinstance(value, (list, tuple)) or hasattr(value, "shape"):
        return v.table({"x": value}, where)["x"]
    return v.scalar(value, where)


def _simulation_property(key, doc):
    """A [simulation] key as an attribute: `s.dt = 1e-4` is s.set_simulation(dt=1e-4)."""
    def get(self):
        return self._simulation.get(key)

    def set(self, value):
        self.set_simulation(**{key: value})

    return property(get, set, doc=doc + " (None: not set; set_simulation sets several at once)")


class Scene(Bodies):
    """A scene built in Python: materials, shapes, drivers, particles, particle grids, rock masses,
    checks and the run settings, in SI units (angles in degrees, as in scene files; any number may
    also be a string with a unit, "30 deg", "2 GPa").

        s = polydem.Scene("falling-cube", dt=1e-4, end_time=0.5)
        s.add_material("rock", density=2650, kn=1e8, ks=5e7, friction_angle=30)
        s.add_shape("cube", box=(1, 1, 1))
        s.add_particle("cube", "rock", position=(0, 0, 2))
        sim = polydem.Simulation(s)

    Particles get uids 1, 2, ... in the order they are added (grids x fastest, then y, z; a rock
    mass its blocks in cutting order); add_particle and add_particle_grid return them.
    """

    def __init__(self, id="python-scene", title=None, description=None, source=None, **simulation):
        self._scene = {"id": v.name(id, "Scene id")}
        for key, value in (("title", title), ("description", description), ("source", source)):
            if value is not None:
                self._scene[key] = v.text(value, "Scene " + key)
        self._simulation = {}
        self._sections = {}  # kernel_params, domain, ... : dicts
        self._entries = {"material": [], "interaction": [], "joint": [], "shape": [],
                         "driver": [], "check": [], "bolt": []}
        self._bodies = []  # ("particle" | "particle_grid" | "rock_mass", dict), in order
        self._particle_uids = {}  # uid of a single particle -> its dict
        self._next_uid = 1
        self._built = None
        self.set_simulation(**simulation)

    # --- run settings ------------------------------------------------------------------------
    dt = _simulation_property("dt", "Time step [s]")
    end_time = _simulation_property("end_time", "Simulated time the run stops at [s]")
    steps = _simulation_property("steps", "Step count the run stops at")
    gravity = _simulation_property("gravity", "Gravity [m/s^2], (x, y, z)")
    kernel = _simulation_property("kernel", "Contact kernel (polydem.kernels())")
    contact_model = _simulation_property("contact_model", "'sub-contacts' or 'point'")

    def set_simulation(self, **settings):
        """Sets keys of [simulation]: kernel, broadphase, contact_model, contact_point, dt,
        end_time, steps, gravity, contact_margin (None removes a key). All or nothing: the
        settings are checked on a copy, so one bad value leaves every key as it was."""
        table = dict(self._simulation)
        for key, value in settings.items():
            if key not in _SIMULATION_KEYS:
                raise TypeError("set_simulation: unknown key %r (known: %s)"
                                % (key, ", ".join(_SIMULATION_KEYS)))
            where = "Scene %s" % key
            if value is None:
                table.pop(key, None)
            elif key in ("kernel", "broadphase", "contact_model", "contact_point"):
                table[key] = v.name(value, where)
            elif key == "steps":
                table[key] = v.integer(value, where, 1)
            elif key == "gravity":
                table[key] = v.vec3(value, where)
            elif key == "contact_margin":
                table[key] = v.scalar(value, where, 0.0)
            else:  # dt, end_time
                table[key] = v.scalar(value, where, 0.0, exclusive=True)
        self._simulation = table
        self._changed()
        return self

    def _set(self, section, settings):
        known = _SECTION_KEYS[section]
        table = dict(self._sections.get(section, {}))
        for key, value in settings.items():
            if key not in known:
                raise TypeError("set_%s: unknown key %r (known: %s)" % (section, key,
                                                                       ", ".join(known)))
            if value is None:
                table.pop(key, None)
            elif section == "seismic" and key in _RECORD_KEYS:
                # A record file given from Python is where the working directory says; the
                # absolute path keeps it found wherever the scene is saved or built.
                table[key] = os.path.abspath(os.fspath(value))
            else:
                table[key] = _entry_value(key, value, "[%s] %s" % (section, key))
        self._sections[section] = table
        self._changed()
        return self

    def set_kernel_params(self, **settings):
        """[kernel_params]: lp_rounding."""
        return self._set("kernel_params", settings)

    def set_domain(self, **settings):
        """[domain]: min, max, blocks, periodic, rebalance_every, balancer, sort_every."""
        return self._set("domain", settings)

    def set_equilibrium(self, **settings):
        """[equilibrium] (the initial-equilibrium stage; enabled by calling this): enabled,
        local_damping, friction_angle, force_ratio, max_steps, reset_velocities."""
        return self._set("equilibrium", settings)

    def set_output(self, **settings):
        """[output]: series_every, snapshot_every, progress_every, monitor (labels)."""
        return self._set("output", settings)

    def set_checkpoint(self, **settings):
        """[checkpoint] of polydem.run: every_steps, every_seconds, keep."""
        return self._set("checkpoint", settings)

    def set_fos(self, **settings):
        """[fos] of polydem fos: interactions, f_min, f_max, resolution, max_time, ..."""
        return self._set("fos", settings)

    def set_water(self, **settings):
        """[water] (water pressure on the joint faces, docs/scene-format.md "Water in the
        joints"): unit_weight [N/m^3], and the phreatic surface: level [m], or points (three
        [x, y, z]: a plane; more: a surface triangulated in plan), or table (rows [time, level]),
        or points as [x, y] with a table of rows [time, z1 .. zN]. joint: a list of dicts, each
        {"joint": NAME, and its own level, points, table, or "dry": True} ([[water.joint]]: a
        surface on the faces of that [[joint]], plane or joint set); with joint, the global
        surface may be left out (dry elsewhere). None removes a key; water=None (the property)
        removes the table."""
        return self._set("water", settings)

    @property
    def water(self):
        """The [water] settings as given (a dict), or None when the scene has no water."""
        table = self._sections.get("water")
        return dict(table) if table else None

    @water.setter
    def water(self, settings):
        if settings is None:
            self._sections.pop("water", None)
            self._changed()
            return
        if not isinstance(settings, dict):
            raise TypeError("Scene water must be a dict of [water] keys or None, got %s"
                            % type(settings).__name__)
        previous = self._sections.pop("water", None)
        try:
            self._set("water", settings)
        except (TypeError, ValueError):
            if previous is not None:
                self._sections["water"] = previous
            raise

    def set_seismic(self, **settings):
        """[seismic] (the pseudo-static earthquake load, docs/scene-format.md "Earthquakes"):
        kh (horizontal, a fraction of g) with its azimuth (degrees clockwise from north = +y,
        where the load pushes), kv (vertical, a fraction of g, positive upward). None removes a
        key; seismic=None (the property) removes the table."""
        return self._set("seismic", settings)

    @property
    def seismic(self):
        """The [seismic] settings as given (a dict), or None when the scene has no earthquake."""
        table = self._sections.get("seismic")
        return dict(table) if table else None

    @seismic.setter
    def seismic(self, settings):
        if settings is None:
            self._sections.pop("seismic", None)
            self._changed()
            return
        if not isinstance(settings, dict):
            raise TypeError("Scene seismic must be a dict of [seismic] keys or None, got %s"
                            % type(settings).__name__)
        previous = self._sections.pop("seismic", None)
        try:
            self._set("seismic", settings)
        except (TypeError, ValueError):
            if previous is not None:
                self._sections["seismic"] = previous
            raise

    # --- tables ------------------------------------------------------------------------------
    def add_material(self, name, density, kn=0.0, ks=0.0, friction_angle=0.0, cohesion=0.0,
                     normal_damping=0.0, local_damping=0.0, penalty=0.0, jkn=0.0, jks=0.0):
        """Adds a [[material]]: density [kg/m^3] > 0; kn, ks [N/m]; friction_angle [deg] in
        [0, 90); cohesion [N]; normal_damping (fraction of critical); local_damping in [0, 1);
        penalty [Pa]; jkn, jks [Pa/m]. kn > 0 or penalty > 0 is required."""
        where = "add_material(%r)" % (name,)
        v.name(name, where + " name")
        self._unique("material", name, where)
        m = {"name": name, "density": v.scalar(density, where + ": density", 0.0, True)}
        values = dict(kn=kn, ks=ks, friction_angle=friction_angle, cohesion=cohesion,
                      normal_damping=normal_damping, local_damping=local_damping,
                      penalty=penalty, jkn=jkn, jks=jks)
        for key, value in values.items():
            maximum = 90.0 if key == "friction_angle" else 1.0 if key == "local_damping" else None
            checked = v.scalar(value, "%s: %s" % (where, key), 0.0, maximum=maximum)
            if checked != 0.0:  # 0 is every key's default: the file stays short
                m[key] = checked
        if not isinstance(kn, str) and not isinstance(penalty, str) and not (
                m.get("kn", 0.0) > 0 or m.get("penalty", 0.0) > 0):
            raise ValueError(where + ": kn > 0 or penalty > 0 is required")
        self._entries["material"].append(m)
        self._changed()
        return self

    def add_joint(self, name, law="coulomb", **parameters):
        """Adds a [[joint]] (docs/scene-format.md, "Joints"): its `law` ("coulomb",
        "coulomb-residual", "barton-bandis") and that law's parameters as keywords, numbers in
        SI units (angles in degrees) or strings with a unit ("10 GPa/m", "50 kPa"), flags as
        True/False. The scene reader checks them as in a file: each law's keys, units, ranges
        and defaults. A rock mass's plane or joint set takes it with joint=name."""
        where = "add_joint(%r)" % (name,)
        v.name(name, where + " name")
        self._unique("joint", name, where)
        j = {"name": name, "law": v.name(law, where + ": law")}
        for key, value in parameters.items():
            if isinstance(value, bool):
                j[key] = value
            else:
                j[key] = v.scalar(value, "%s: %s" % (where, key))
        # Units and ranges, as the reader checks them, in a scene of one probe particle.
        material = {"name": "probe material", "density": 1.0, "kn": 1.0}
        shape = {"name": "probe shape", "type": "cube", "edge": 1.0}
        body = {"shape": shape["name"], "material": material["name"]}
        self._probe([("joint", j, True), ("material", material, True), ("shape", shape, True),
                     ("particle", body, True)], where)
        self._entries["joint"].append(j)
        self._changed()
        return self

    def set_material(self, name, **values):
        """Changes keys of the material `name` (those of add_material)."""
        m = self._find("material", name, "set_material")
        trial = dict(m)
        trial.update(values)
        del trial["name"]
        entries = self._entries["material"]
        i = entries.index(m)
        entries.pop(i)
        try:
            self.add_material(name, **trial)
        except Exception:
            entries.insert(i, m)
            raise
        entries.insert(i, entries.pop())
        return self

    def add_material_pair(self, a, b, **properties):
        """Adds an [[interaction]]: the contact properties of materials `a` and `b` (kn, ks,
        friction_angle, cohesion, normal_damping, penalty, jkn, jks); keys not given keep the
        default rule (min of springs, friction and cohesion, mean damping)."""
        where = "add_material_pair(%r, %r)" % (a, b)
        for m in (a, b):
            self._find("material", m, where)
        for e in self._entries["interaction"]:
            if sorted(e["materials"]) == sorted([a, b]):
                raise ValueError(where + ": this pair is already given")
        entry = {"materials": [a, b]}
        for key, value in properties.items():
            if key not in _CONTACT_KEYS:
                raise TypeError("%s: unknown key %r (known: %s)" % (where, key,
                                                                   ", ".join(_CONTACT_KEYS)))
            entry[key] = v.scalar(value, "%s: %s" % (where, key), 0.0,
                                  maximum=90.0 if key == "friction_angle" else None)
        self._entries["interaction"].append(entry)
        self._changed()
        return self

    add_interaction = add_material_pair

    def add_shape(self, name, type=None, vertices=None, box=None, rotation=None, scale=None,
                  **params):
        """Adds a [[shape]]. `vertices` ((n, 3): their convex hull, where given), `box` ((x, y,
        z) sizes, centred), or `type` with its keys: prism (polygon, height), triangular_prism
        (length, width, height), pyramid (base, height, apex), tetrahedron, cube, octahedron,
        dodecahedron, icosahedron (edge), hexagonal_prism (radius, length), random (count,
        radius, seed), box (size or min/max). `rotation` and `scale` apply to the vertices."""
        where = "add_shape(%r)" % (name,)
        v.name(name, where + " name")
        self._unique("shape", name, where)
        if sum(x is not None for x in (type, vertices, box)) != 1:
            raise TypeError(where + ": give exactly one of type=..., vertices=..., box=...")
        shape = {"name": name}
        if vertices is not None:
            shape["type"] = "vertices"
            shape["vertices"] = v.array(vertices, where + ": vertices", (None, 3))
        elif box is not None:
            shape["type"] = "box"
            shape["size"] = v.vec3(box, where + ": box")
        else:
            if type not in _SHAPE_TYPES:
                raise ValueError("%s: unknown shape type %r (known: %s)"
                                 % (where, type, ", ".join(_SHAPE_TYPES)))
            shape["type"] = type
        for key, value in params.items():
            if key == "polygon":
                shape[key] = v.array(value, where + ": polygon", (None, 2))
            elif key in ("seed", "count"):
                shape[key] = v.integer(value, "%s: %s" % (where, key), 0)
            elif key == "apex":
                shape[key] = v.name(value, where + ": apex")
            else:
                shape[key] = _entry_value(key, value, "%s: %s" % (where, key))
        if rotation is not None:
            shape["rotation"] = v.rotation(rotation, where + ": rotation")
        if scale is not None:
            per_axis = isinstance(scale, (list, tuple)) or hasattr(scale, "shape")
            shape["scale"] = (v.vec3(scale, where + ": scale") if per_axis
                              else v.scalar(scale, where + ": scale", 0.0, True))
        self._try_entry("shape", shape, where)
        return self

    def add_driver(self, name, velocity=None, angular_velocity=None, pivot=None, oscillation=None,
                   frequency=None, phase=None, start_time=None, end_time=None):
        """Adds a [[driver]], a prescribed motion: velocity [m/s], angular_velocity [rad/s] about
        `pivot` [m] (which moves with the velocity), oscillation [m/s] at `frequency` [Hz] and
        `phase` [rad], between start_time and end_time [s]."""
        where = "add_driver(%r)" % (name,)
        v.name(name, where + " name")
        self._unique("driver", name, where)
        d = {"name": name}
        for key, value in (("velocity", velocity), ("angular_velocity", angular_velocity),
                           ("pivot", pivot), ("oscillation", oscillation)):
            if value is not None:
                d[key] = v.vec3(value, "%s: %s" % (where, key))
        for key, value in (("frequency", frequency), ("phase", phase),
                           ("start_time", start_time), ("end_time", end_time)):
            if value is not None:
                d[key] = v.scalar(value, "%s: %s" % (where, key),
                                  None if key == "phase" else 0.0)
        self._entries["driver"].append(d)
        self._changed()
        return self

    def add_check(self, name, kind, expected=None, tolerance=None, compare=None, reference=None,
                  **params):
        """Adds a [[check]], an expected result of polydem.run: its `kind` and the kind's
        parameters (particle="b1", direction=(1, 0, 0), ...: docs/scene-format.md, "Check
        kinds")."""
        where = "add_check(%r)" % (name,)
        v.name(name, where + " name")
        self._unique("check", name, where)
        c = {"name": name, "kind": v.name(kind, where + ": kind")}
        if expected is not None:
            c["expected"] = v.scalar(expected, where + ": expected")
        if tolerance is not None:
            c["tolerance"] = v.scalar(tolerance, where + ": tolerance", 0.0)
        if compare is not None:
            c["compare"] = v.name(compare, where + ": compare")
        if reference is not None:
            c["reference"] = v.text(reference, where + ": reference")
        for key, value in params.items():
            c[key] = _entry_value(key, value, "%s: %s" % (where, key))
        self._entries["check"].append(c)
        self._changed()
        return self

    def add_bolt(self, name, start, length, axial_stiffness, axial_yield, shear_stiffness=0.0,
                 shear_yield=0.0, direction=None, trend=None, plunge=None, pretension=None,
                 ultimate_elongation=None):
        """Adds a [[bolt]] (docs/scene-format.md, "Rock bolts"): a bolt or cable from `start`
        (x, y, z) over `length` along `direction` (a vector) or `trend` (degrees clockwise from
        north = +y) and `plunge` (degrees below the horizontal); axial_stiffness [N/m] and
        axial_yield [N], shear_stiffness [N/m] and shear_yield [N], an optional pretension [N]
        (tension positive) and ultimate_elongation [m] (the plastic elongation at a joint at which
        it breaks). Numbers in SI units or strings with a unit ("2 MN/m", "150 kN"). The blocks it
        crosses are found when the simulation is built (polydem.InputError naming the bolt if it
        crosses no joint)."""
        where = "add_bolt(%r)" % (name,)
        v.name(name, where + " name")
        self._unique("bolt", name, where)
        b = {"name": name, "start": v.vec3(start, where + ": start")}
        if direction is not None:
            b["direction"] = v.vec3(direction, where + ": direction")
        for key, value in (("trend", trend), ("plunge", plunge), ("length", length),
                           ("axial_stiffness", axial_stiffness), ("axial_yield", axial_yield),
                           ("shear_stiffness", shear_stiffness), ("shear_yield", shear_yield),
                           ("pretension", pretension),
                           ("ultimate_elongation", ultimate_elongation)):
            if value is not None:
                b[key] = v.scalar(value, "%s: %s" % (where, key))
        # Keys, units and ranges, as the reader checks them, in a scene of one probe particle.
        material = {"name": "probe material", "density": 1.0, "kn": 1.0}
        shape = {"name": "probe shape", "type": "cube", "edge": 1.0}
        body = {"shape": shape["name"], "material": material["name"]}
        self._probe([("material", material, True), ("shape", shape, True),
                     ("particle", body, True), ("bolt", b, True)], where)
        self._entries["bolt"].append(b)
        self._changed()
        return self

    def remove_check(self, name):
        """Removes the [[check]] `name` (the reader judges a check's kind and parameters only when
        the scene is built: this takes back one it refused)."""
        self._entries["check"].remove(self._find("check", name, "remove_check"))
        self._changed()
        return self

    @classmethod
    def from_toml(cls, text, name="<string>"):
        """A Scene holding what the scene-file text says (docs/scene-format.md), to change and
        extend; building it gives the scene the file gives. Each [[particle]], [[particle_grid]]
        and [[rock_mass]] must be a [[...]] table of its own (their order gives the uids)."""
        return _scene_load.fill(cls(), v.text(text, "text"), name)

    @classmethod
    def load(cls, path):
        """Scene.from_toml of the scene file at `path` (str or os.PathLike)."""
        path = os.fspath(path)
        with open(path, encoding="utf-8") as f:
            return cls.from_toml(f.read(), path)

    # --- the scene ---------------------------------------------------------------------------
    def to_toml(self):
        """The scene as a scene file (docs/scene-format.md): what save() writes, what a
        checkpoint stores, what `polydem run` reads to make the same run."""
        sections = [("scene", self._scene, False), ("simulation", self._simulation, False)]
        for key, table in self._sections.items():
            sections.append((key, table, False))
        for key in ("material", "interaction", "joint", "shape", "driver"):
            sections += [(key, e, True) for e in self._entries[key]]
        sections += [(kind, b, True) for kind, b in self._bodies]
        sections += [("check", e, True) for e in self._entries["check"]]
        sections += [("bolt", e, True) for e in self._entries["bolt"]]
        return "# Written by polydem.Scene (python_coupling/polydem/scene_builder.py)\n\n" + \
            _toml.document(sections)

    def save(self, path):
        """Writes to_toml() to `path` (str or os.PathLike); returns the path."""
        path = os.fspath(path)
        with open(path, "w", encoding="utf-8") as f:
            f.write(self.to_toml())
        return path

    def build(self):
        """The checked scene (a polydem.SceneData) as polydem's scene reader makes it from
        to_toml(); cached until the scene changes. Raises polydem.InputError for what the reader
        refuses (its message names the line of to_toml())."""
        if self._built is None:
            self._built = parse_scene(self.to_toml(), "<polydem.Scene '%s'>" % self._scene["id"])
        return self._built

    def __getattr__(self, attr):
        # Read-only views of the built scene (particles, materials, shapes, rock_masses, ...).
        if attr.startswith("_") or attr not in _BUILT_VIEWS:
            raise AttributeError("'Scene' object has no attribute %r" % attr)
        return getattr(self.build(), attr)

    def __repr__(self):
        return "polydem.Scene(%r: %d materials, %d shapes, %d particles)" % (
            self._scene["id"], len(self._entries["material"]), len(self._entries["shape"]),
            self._next_uid - 1)

    # --- helpers -----------------------------------------------------------------------------
    def _changed(self):
        self._built = None

    def _find(self, kind, name, where):
        for e in self._entries[kind]:
            if e["name"] == name:
                return e
        known = ", ".join(repr(e["name"]) for e in self._entries[kind]) or "none yet"
        raise ValueError("%s: unknown %s %r (known: %s)" % (where, kind, name, known))

    def _unique(self, kind, name, where):
        if any(e["name"] == name for e in self._entries[kind]):
            raise ValueError("%s: a %s named %r already exists" % (where, kind, name))

    def _labels_taken(self):
        return {b["label"] for kind, b in self._bodies if kind == "particle" and "label" in b}

    def _probe_text(self, extra):
        """A scene of the materials, joints and `extra` alone, to have the reader check one
        entry."""
        sections = [("scene", {"id": "probe"}, False),
                    ("simulation", {"dt": 1.0, "steps": 1}, False)]
        sections += [("material", e, True) for e in self._entries["material"]]
        sections += [("joint", e, True) for e in self._entries["joint"]]
        return _toml.document(sections + extra)

    def _probe(self, extra, where):
        """Has the reader check `extra` (entries) in a scene of the materials; returns that scene.
        ValueError with the reader's message, without the probe's 'file:line: '."""
        try:
            return parse_scene(self._probe_text(extra), "<%s>" % where)
        except InputError as e:
            raise ValueError("%s: %s" % (where, _message(e))) from None

    def _try_entry(self, kind, entry, where):
        # A shape is checked as the one shape of a one-particle scene of a material of its own.
        probe = {"name": "probe material", "density": 1.0, "kn": 1.0}
        body = {"shape": entry["name"], "material": probe["name"]}
        self._probe([("material", probe, True), (kind, entry, True), ("particle", body, True)],
                    where)
        self._entries[kind].append(entry)
        self._changed()


def _message(error):
    """The reader's message without the 'file:line: ' of the probe, which the user never saw."""
    text = str(error)
    for prefix in ("%s:%s: " % (error.file, error.line), "%s: " % error.file):
        if text.startswith(prefix):
            return text[len(prefix):]
    return text


_BUILT_VIEWS = ("particles", "num_particles", "materials", "shapes", "drivers", "rock_masses",
                "checks", "monitor", "equilibrium", "file", "broadphase", "bolts")

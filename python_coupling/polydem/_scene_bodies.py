"""The bodies of polydem.Scene: particles, particle grids and rock masses, in the order they are
added, which gives their uids (scene_builder.py holds the rest of the scene)."""
from . import _values as v


class Bodies:
    """Methods of polydem.Scene that add and change bodies; they use the scene's tables
    (self._find, self._entries) and its list of bodies (self._bodies, in order)."""

    def add_particle(self, shape, material, position=(0.0, 0.0, 0.0), orientation=None,
                     velocity=None, angular_velocity=None, fixed=False, driver=None, label=None,
                     rotation=None):
        """Adds a [[particle]] and returns its uid. `position` [m] is the centroid of a built-in
        shape (a `vertices` shape moves from where its vertices are); `orientation` a quaternion
        (w, x, y, z) or `rotation` as in scene files ({"axis": .., "angle": deg}, ...);
        velocity [m/s], angular_velocity [rad/s]; `fixed` bodies move only with the ground of a
        [seismic] record; `driver` names a prescribed motion; `label` (unique) names the
        particle for checks and monitors."""
        p = self._particle(dict(shape=shape, material=material, position=position,
                                orientation=orientation, velocity=velocity,
                                angular_velocity=angular_velocity, fixed=fixed, driver=driver,
                                label=label, rotation=rotation), None)
        uid = self._next_uid
        self._bodies.append(("particle", p))
        self._particle_uids[uid] = p
        self._next_uid += 1
        self._changed()
        return uid

    def set_particle(self, uid, **values):
        """Changes keys of the particle `uid` added with add_particle (those of add_particle:
        position, orientation or rotation, velocity, angular_velocity, fixed, driver, label)."""
        old = self._particle_uids.get(uid)
        if old is None:
            raise ValueError("set_particle: no particle added with add_particle has uid %r"
                             % (uid,))
        args = {k: old.get(k) for k in ("shape", "material", "position", "velocity",
                                         "angular_velocity", "driver", "label", "rotation")}
        args["fixed"] = old.get("fixed", False)
        if "orientation" in values:
            args["rotation"] = None  # the new orientation replaces the rotation it had
        args.update(values)
        new = self._particle(args, old.get("label"))
        index = next(i for i, (_, b) in enumerate(self._bodies) if b is old)
        self._bodies[index] = ("particle", new)
        self._particle_uids[uid] = new
        self._changed()
        return self

    def _particle(self, a, own_label):
        """The [[particle]] entry of add_particle's arguments `a`; `own_label` is the label the
        particle being changed has (it may keep it)."""
        unknown = set(a) - {"shape", "material", "position", "orientation", "velocity",
                            "angular_velocity", "fixed", "driver", "label", "rotation"}
        if unknown:
            raise TypeError("set_particle: unknown key(s) %s" % ", ".join(sorted(unknown)))
        where = "add_particle(%r, %r)" % (a["shape"], a["material"])
        self._find("shape", a["shape"], where)
        self._find("material", a["material"], where)
        p = {"shape": a["shape"], "material": a["material"],
             "position": v.vec3(a.get("position", (0.0, 0.0, 0.0)), where + ": position")}
        orientation, rotation = a.get("orientation"), a.get("rotation")
        if orientation is not None and rotation is not None:
            raise TypeError(where + ": give orientation or rotation, not both")
        if orientation is not None:
            p["rotation"] = v.quaternion(orientation, where + ": orientation")
        if rotation is not None:
            p["rotation"] = v.rotation(rotation, where + ": rotation")
        for key in ("velocity", "angular_velocity"):
            if a.get(key) is not None:
                p[key] = v.vec3(a[key], "%s: %s" % (where, key))
        fixed = v.boolean(a.get("fixed", False), where + ": fixed")
        if fixed:
            p["fixed"] = True
        if a.get("driver") is not None:
            self._find("driver", a["driver"], where)
            if fixed:
                raise ValueError(where + ": a particle is either fixed or driven, not both")
            p["driver"] = a["driver"]
        label = a.get("label")
        if label is not None:
            v.name(label, where + ": label")
            if label != own_label and label in self._labels_taken():
                raise ValueError("%s: the label %r is already used" % (where, label))
            p["label"] = label
        return p

    def add_particle_grid(self, shape, material, count, spacing, origin=(0.0, 0.0, 0.0),
                          orientation=None, rotation=None, velocity=None, jitter=None, seed=None,
                          label_prefix=None):
        """Adds a [[particle_grid]], count[0] x count[1] x count[2] particles on a lattice of
        `spacing` [m] (a number or (dx, dy, dz)) from `origin`, x fastest; `jitter` [m] moves
        each coordinate by a uniform amount drawn from `seed`; labels "<label_prefix>_i_j_k".
        Returns their uids (a range)."""
        where = "add_particle_grid(%r, %r)" % (shape, material)
        self._find("shape", shape, where)
        self._find("material", material, where)
        n = v.array(count, where + ": count", (3,))
        n = [v.integer(c, where + ": count", 1) for c in n]
        g = {"shape": shape, "material": material, "count": n,
             "origin": v.vec3(origin, where + ": origin")}
        if isinstance(spacing, (list, tuple)) or hasattr(spacing, "shape"):
            g["spacing"] = v.vec3(spacing, where + ": spacing")
        else:
            g["spacing"] = v.scalar(spacing, where + ": spacing", 0.0, True)
        if orientation is not None:
            g["rotation"] = v.quaternion(orientation, where + ": orientation")
        if rotation is not None:
            g["rotation"] = v.rotation(rotation, where + ": rotation")
        if velocity is not None:
            g["velocity"] = v.vec3(velocity, where + ": velocity")
        if jitter is not None:
            g["jitter"] = v.scalar(jitter, where + ": jitter", 0.0)
        if seed is not None:
            g["seed"] = v.integer(seed, where + ": seed", 0)
        if label_prefix is not None:
            g["label_prefix"] = v.name(label_prefix, where + ": label_prefix")
        first = self._next_uid
        self._bodies.append(("particle_grid", g))
        self._next_uid += n[0] * n[1] * n[2]
        self._changed()
        return range(first, self._next_uid)

    def add_rock_mass(self, name, material, region, joint_sets=(), planes=(), fixed_material=None,
                      label_prefix=None, min_volume=None, min_thickness=None, slivers=None,
                      joints_cut_fixed=None, max_blocks=None):
        """Adds a [[rock_mass]]: `region` ({"type": "box", "min": .., "max": ..}, {"type":
        "polyhedron", "vertices": ..} or {"type": "profile", "profile": [(x, z), ..], "y": (y0,
        y1)}) cut by `planes` (dicts: name, dip, dip_direction, point, fixed, remove, joint) and
        then `joint_sets` (dicts: name, dip, dip_direction, spacing, offset, origin,
        spacing_jitter, orientation_jitter, seed, joint); `joint` names an add_joint() joint;
        angles in degrees (docs/scene-format.md). The region is cut
        now (errors are raised here); returns the uids of the blocks (a range)."""
        where = "add_rock_mass(%r)" % (name,)
        v.name(name, where + " name")
        self._find("material", material, where)
        r = {"name": name, "material": material, "region": v.table(region, where + ": region")}
        if fixed_material is not None:
            self._find("material", fixed_material, where)
            r["fixed_material"] = fixed_material
        for key, value in (("label_prefix", label_prefix), ("slivers", slivers)):
            if value is not None:
                r[key] = v.name(value, "%s: %s" % (where, key))
        for key, value in (("min_volume", min_volume), ("min_thickness", min_thickness)):
            if value is not None:
                r[key] = v.scalar(value, "%s: %s" % (where, key), 0.0)
        if joints_cut_fixed is not None:
            r["joints_cut_fixed"] = v.boolean(joints_cut_fixed, where + ": joints_cut_fixed")
        if max_blocks is not None:
            r["max_blocks"] = v.scalar(max_blocks, where + ": max_blocks", 0.0, exclusive=True)
        for key, items in (("joint_set", joint_sets), ("plane", planes)):
            if not isinstance(items, (list, tuple)):
                raise TypeError("%s: %ss must be a list of dicts" % (where, key))
            if items:
                r[key] = [v.table(x, "%s: %s" % (where, key)) for x in items]
        # Cut it now, alone, with the materials: how many blocks it makes fixes the uids of the
        # bodies after it, and a bad description is reported at this call.
        blocks = self._probe([("rock_mass", r, True)], where).num_particles
        first = self._next_uid
        self._bodies.append(("rock_mass", r))
        self._next_uid += blocks
        self._changed()
        return range(first, self._next_uid)

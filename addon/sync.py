"""Keep the viewport's Scene in step with Blender's edits, re-reading only what changed.

A depsgraph update names the data blocks it touched. `changed_parts` sorts them into the
parts the pipeline's caches depend on (docs/architecture.md, "A viewport update: what
each edit redoes"): the camera, the lights (with the world), the geometry (triangles,
albedo and point emitters) and the point emitters alone (an instancer moved whose
instances are all point emitters and that draws nothing itself: particles in motion).
`SceneSync` then re-extracts just those parts, so a camera move costs no extraction and
keeps every cached light map and the LPV, and moving particles are read in bulk without
the walk over the depsgraph's instances; the pipeline's content keys decide the rest.
"""
from dataclasses import dataclass, replace

from ..gpu.scene import Scene
from .extract import MESH_LIKE_TYPES, extract_parts, extract_point_emitters, render_settings_of
from .world import world_and_lights

CAMERA, LIGHTS, GEOMETRY, EMITTERS = "camera", "lights", "geometry", "emitters"
EVERYTHING = frozenset((CAMERA, LIGHTS, GEOMETRY))

GEOMETRY_DATA = {"MESH", "MATERIAL", "NODETREE", "IMAGE", "CURVE", "METABALL", "TEXT", "CURVES",
                 "POINTCLOUD", "VOLUME"}
"""Data blocks whose edits change triangles or albedo (`ID.id_type`)."""

EVERYTHING_DATA = {"COLLECTION", "SCENE"}
"""Edits that may show or hide anything: visibility, instancing, the active camera."""

PART_DATA = {"OBJECT", "LIGHT", "CAMERA", "WORLD"} | GEOMETRY_DATA | EVERYTHING_DATA
"""Data blocks whose edits `changed_parts` sorts into the parts (or leaves out, as the
scene's own settings)."""

INSTANCER_TYPES = MESH_LIKE_TYPES | {"EMPTY", "CURVE", "FONT", "CURVES", "POINTCLOUD", "VOLUME"}
"""Object types whose own edits move triangles (their own or their instances')."""


@dataclass(frozen=True)
class RecordedUpdate:
    """What one `DepsgraphUpdate` said, kept as plain values (the update itself is only
    valid inside the handler or `view_update` call that received it)."""

    id_type: str          # ID.id_type: "OBJECT", "MESH", "MATERIAL", ...
    object_type: str      # Object.type for objects, else ""
    geometry: bool        # is_updated_geometry
    transform: bool       # is_updated_transform
    shading: bool         # is_updated_shading
    pointer: int          # the original data block's address

    @classmethod
    def record(cls, update):
        data = update.id
        return cls(data.id_type, data.type if data.id_type == "OBJECT" else "", update.is_updated_geometry,
                   update.is_updated_transform, update.is_updated_shading, data.original.as_pointer())


def record_updates(depsgraph):
    return [RecordedUpdate.record(update) for update in depsgraph.updates]


def edits_cycles_sees(updates, parts):
    """Whether `updates`, which changed the `parts` (changed_parts), hold an edit that
    changes what Cycles renders beyond the camera: one that changes a part of the scene
    but the camera, or a data block no part reads (the world, say), which Cycles renders
    all the same."""
    return bool(parts - {CAMERA}) or any(update.id_type not in PART_DATA for update in updates)


def changed_parts(updates, emitters_alone=frozenset()):
    """The parts of the scene (CAMERA, LIGHTS, GEOMETRY, EMITTERS) that `updates` may have
    changed; `emitters_alone`, the original pointers of the instancers whose edits move
    point emitters alone (SceneSync.emitters_alone)."""
    parts = set()
    for update in updates:
        if update.id_type == "OBJECT":
            if update.object_type == "LIGHT":
                parts.add(LIGHTS)
            elif update.object_type == "CAMERA":
                parts.add(CAMERA)
            elif update.object_type in INSTANCER_TYPES and (update.geometry or update.transform or update.shading):
                parts.add(EMITTERS if update.pointer in emitters_alone else GEOMETRY)
        elif update.id_type in ("LIGHT", "WORLD"):
            parts.add(LIGHTS)
        elif update.id_type == "CAMERA":
            parts.add(CAMERA)
        elif update.id_type in GEOMETRY_DATA:
            parts.add(GEOMETRY)
        elif update.id_type in EVERYTHING_DATA and (update.geometry or update.transform):
            parts.update(EVERYTHING)
    return frozenset(parts)


class SceneSync:
    """The sanitized Scene a viewport shows, re-extracted part by part."""

    def __init__(self):
        self._scene = None
        self.extracted = ()  # the parts the last `scene` call read from Blender
        self.emitters_alone = frozenset()  # instancers whose edits move point emitters alone (changed_parts)

    def scene(self, depsgraph, parts, camera, view3d=None):
        """The current Scene with `camera`; re-reads the `parts` that changed (all of them
        the first time). Keeps the sanitized geometry and its content key otherwise."""
        first = self._scene is None
        read_geometry, read_lights = first or GEOMETRY in parts, first or LIGHTS in parts
        moved_alone = EMITTERS in parts and not read_geometry
        if moved_alone:
            moved_alone = self._moved_emitters(depsgraph, view3d)
            read_geometry = not moved_alone  # else an instancer no longer moves point emitters alone
        self.extracted = tuple(part for part, read in ((GEOMETRY, read_geometry), (LIGHTS, read_lights),
                                                       (EMITTERS, moved_alone)) if read)
        if not read_geometry and not read_lights:
            self._scene = self._scene.in_local_frame(camera=camera)
            return self._scene
        geometry, lights, emitters = extract_parts(depsgraph, view3d, read_geometry, read_lights)
        if emitters is not None:
            self.emitters_alone = frozenset(emitters.alone_instancers)
        if read_lights:  # the world goes with the lights, its Sky Textures' suns among them
            world, lights = world_and_lights(depsgraph.scene_eval, lights)
        else:
            world = self._scene.world
        if read_geometry:
            lights = lights if read_lights else self._scene.world_lights()
            settings = render_settings_of(depsgraph.scene_eval, viewport=True)
            self._scene = Scene(**geometry, lights=[], **settings).in_local_frame(lights, camera, world)
            self._scene = self._scene.sanitize()
        else:
            self._scene = self._scene.in_local_frame(lights, camera, world)
            self._scene.require_lights()
        return self._scene

    def _moved_emitters(self, depsgraph, view3d):
        """Put the point emitters read anew, alone, into the kept Scene, where the same
        instancers still move point emitters alone; False (nothing changed) otherwise."""
        emitters = extract_point_emitters(depsgraph, view3d)
        if frozenset(emitters.alone_instancers) != self.emitters_alone:
            return False
        self._scene = replace(self._scene, point_emitters=emitters.array(self._scene.world_origin))
        self._scene.require_lights()
        return True

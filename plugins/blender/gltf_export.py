# One frame of the evaluated scene as a glTF file: export_frame_gltf(depsgraph, path).
#
# The add-on walks the depsgraph Blender hands to RenderEngine.render() itself instead of running
# Blender's glTF export operator. The operator needs a window context that render() does not
# have (`blender -b file.blend -f 1` fails inside it), evaluates the view layer's viewport
# depsgraph rather than the render one, and exports armature-deformed and shape-keyed meshes in
# their rest shape (as skins and morph targets). Here every object instance of the render
# depsgraph is written as it is at this frame: meshes with modifiers, armature poses, shape keys
# and geometry nodes applied (obj.to_mesh() of the evaluated object), instances (collections,
# particles, geometry nodes) as nodes sharing one mesh, the scene camera, and the lights glTF's
# KHR_lights_punctual carries, in the units Blender's own exporter writes (which libveach's
# importer reads back as Blender means them). Materials are converted by materials.py.
#
# What cannot be carried goes into Export.warnings, one message per kind, for self.report.
# Hooks: functions in post_export_hooks are called as hook(gltf, depsgraph, export) on the glTF
# JSON (a dict) before it is written, so other converters (lights glTF lacks) can add to it.
import json
import math
import os

import numpy as np

from . import blender_lights, materials

# Blender is Z up, glTF Y up: glTF (x, y, z) = Blender (x, z, -y).
TO_GLTF = np.array([[1, 0, 0, 0], [0, 0, 1, 0], [0, -1, 0, 0], [0, 0, 0, 1]], dtype=np.float64)
# Blender's exporter: W to candela for point and spot lights, W/m^2 to lux for the sun.
WATTS_TO_LUMENS = 683.0
GENERATOR = "Veach Blender add-on (Khronos glTF Blender I/O conventions)"

post_export_hooks = []

GEOMETRY_TYPES = {"MESH", "CURVE", "SURFACE", "FONT", "META"}


class Export:
    """What one export produced: the glTF JSON, the camera's node name, and the warnings."""

    def __init__(self):
        self.gltf = None
        self.camera_name = None
        self.motion = False  # motion blur: something moves across the shutter (add_motion)
        self.warnings = {}  # kind -> message, first occurrence wins

    def warn(self, kind, message):
        self.warnings.setdefault(kind, message)


class Writer:
    """Accumulates the binary buffer, accessors and buffer views."""

    def __init__(self):
        self.blob = bytearray()
        self.views = []
        self.accessors = []

    def add(self, array, component, kind, target=None, bounds=False):
        data = np.ascontiguousarray(array)
        while len(self.blob) % 4:
            self.blob.append(0)
        view = {"buffer": 0, "byteOffset": len(self.blob), "byteLength": data.nbytes}
        if target:
            view["target"] = target
        self.blob += data.tobytes()
        self.views.append(view)
        accessor = {"bufferView": len(self.views) - 1, "componentType": component,
                    "count": int(data.shape[0]), "type": kind}
        if bounds:
            accessor["min"] = data.min(axis=0).tolist()
            accessor["max"] = data.max(axis=0).tolist()
        self.accessors.append(accessor)
        return len(self.accessors) - 1


def matrix_array(m):
    return np.array([list(row) for row in m], dtype=np.float64)


def column_major(m):
    return [float(x) for x in m.T.ravel()]


def object_matrix(m):
    """A mesh's world matrix in glTF space (its vertices are converted too)."""
    return TO_GLTF @ m @ TO_GLTF.T


def frame_matrix(m):
    """A camera's or light's world matrix in glTF space: both look down their local -Z with +Y
    up in Blender and in glTF, so only the world axes change; scale is dropped."""
    g = TO_GLTF @ m
    for c in range(3):
        length = np.linalg.norm(g[:3, c])
        if length > 0:
            g[:3, c] /= length
    return g


def motion_key(instance):
    """What names one object instance across the depsgraph's re-evaluations within a shutter."""
    return (instance.object.name, instance.is_instance,
            tuple(instance.persistent_id) if instance.is_instance else ())


def world_matrices(depsgraph, shapes=None):
    """Per object instance (motion_key) its world matrix in glTF space as the depsgraph stands:
    one motion blur step. Meshes and cameras only: lights, like emitters, are not blurred. With
    `shapes` (a dict), each object's (not instance's) evaluated corner positions and normals go
    there too, for deformation within the shutter."""
    out = {}
    for instance in depsgraph.object_instances:
        obj = instance.object
        if obj.type in GEOMETRY_TYPES:
            out[motion_key(instance)] = object_matrix(matrix_array(instance.matrix_world))
            if shapes is not None and not instance.is_instance:
                try:
                    mesh = obj.to_mesh()
                except RuntimeError:
                    continue
                try:
                    arrays = mesh_arrays(mesh) if mesh is not None else None
                    if arrays is not None:
                        shapes[motion_key(instance)] = (arrays[0], arrays[1])
                finally:
                    obj.to_mesh_clear()
        elif obj.type == "CAMERA":
            out[motion_key(instance)] = frame_matrix(matrix_array(instance.matrix_world))
    return out


def quaternion_of(r):
    """(x, y, z, w) of the rotation matrix r (Shepperd's method: the largest diagonal term)."""
    t = np.trace(r)
    if t > 0:
        s = 2 * np.sqrt(1 + t)
        q = [(r[2, 1] - r[1, 2]) / s, (r[0, 2] - r[2, 0]) / s, (r[1, 0] - r[0, 1]) / s, s / 4]
    elif r[0, 0] > r[1, 1] and r[0, 0] > r[2, 2]:
        s = 2 * np.sqrt(max(0.0, 1 + r[0, 0] - r[1, 1] - r[2, 2]))
        q = [s / 4, (r[0, 1] + r[1, 0]) / s, (r[0, 2] + r[2, 0]) / s, (r[2, 1] - r[1, 2]) / s]
    elif r[1, 1] > r[2, 2]:
        s = 2 * np.sqrt(max(0.0, 1 + r[1, 1] - r[0, 0] - r[2, 2]))
        q = [(r[0, 1] + r[1, 0]) / s, s / 4, (r[1, 2] + r[2, 1]) / s, (r[0, 2] - r[2, 0]) / s]
    else:
        s = 2 * np.sqrt(max(0.0, 1 + r[2, 2] - r[0, 0] - r[1, 1]))
        q = [(r[0, 2] + r[2, 0]) / s, (r[1, 2] + r[2, 1]) / s, s / 4, (r[1, 0] - r[0, 1]) / s]
    q = np.array(q)
    return q / np.linalg.norm(q)


def trs_of(m):
    """glTF's translation, rotation and scale of a 4x4 matrix (shear, which TRS cannot hold, is
    dropped); None for a singular one."""
    linear = m[:3, :3]
    scale = np.linalg.norm(linear, axis=0)
    if not np.all(scale > 1e-12):
        return None
    if np.linalg.det(linear) < 0:
        scale[0] = -scale[0]
    return m[:3, 3].copy(), quaternion_of(linear / scale), scale


def add_morph_motion(gltf, writer, node_index, frame_arrays, shapes, time_input, channels, samplers, export):
    """A mesh node that deforms within the shutter: one morph target per step (its corners' shift
    from the frame's shape, positions and normals), weights keyed one-hot at the steps' times, so
    that LINEAR weights move every corner on the straight line between two steps, as the
    renderer's vertex time steps do. False when the shapes do not line up (topology changes)."""
    positions, normals, _, triangles, tri_material = frame_arrays
    if any(p.shape != positions.shape or n.shape != normals.shape for p, n in shapes):
        export.warn("motion blur topology", "a mesh whose topology changes within the shutter keeps the frame's "
                                            "shape (moved with its object, not deformed)")
        return False
    mesh = gltf["meshes"][gltf["nodes"][node_index]["mesh"]]
    for primitive, slot in zip(mesh["primitives"], np.unique(tri_material)):
        used = np.unique(triangles[tri_material == slot].ravel())  # as write_mesh orders them
        primitive["targets"] = [
            {"POSITION": writer.add((p[used] - positions[used]).astype(np.float32), 5126, "VEC3", bounds=True),
             "NORMAL": writer.add((n[used] - normals[used]).astype(np.float32), 5126, "VEC3")}
            for p, n in shapes]
    mesh["weights"] = [0.0] * len(shapes)
    weights = np.eye(len(shapes), dtype=np.float32).ravel()
    samplers.append({"input": time_input, "output": writer.add(weights, 5126, "SCALAR"), "interpolation": "LINEAR"})
    channels.append({"sampler": len(samplers) - 1, "target": {"node": node_index, "path": "weights"}})
    return True


def add_motion(gltf, writer, node_keys, motion, export, frame_arrays=None):
    """Animations that move each node whose world matrix changes across the shutter: its
    matrix becomes TRS keyed at the steps' times (seconds from the frame, LINEAR: the renderer
    slerps the rotation), which the renderer poses at time 0, the frame, and samples across the
    shutter; and morph targets for the meshes whose shape changes (add_morph_motion). `motion`:
    (times, steps, shapes), steps[k] and shapes[k] from world_matrices; frame_arrays: per
    motion_key the mesh_arrays the export wrote (objects used once)."""
    times, steps, step_shapes = motion
    channels, samplers = [], []
    time_input = None

    def input_accessor():
        nonlocal time_input
        if time_input is None:
            time_input = writer.add(np.array(times, dtype=np.float32).reshape(-1, 1), 5126, "SCALAR", bounds=True)
        return time_input

    for node_index, key in node_keys:
        if frame_arrays and key in frame_arrays and "mesh" in gltf["nodes"][node_index]:
            shapes = [shape.get(key) for shape in step_shapes]
            frame = frame_arrays[key]
            if all(sh is not None for sh in shapes) and not all(
                    sh[0].shape == frame[0].shape and np.array_equal(sh[0], frame[0]) for sh in shapes):
                add_morph_motion(gltf, writer, node_index, frame, shapes, input_accessor(), channels, samplers,
                                 export)
        mats = [step.get(key) for step in steps]
        if any(m is None for m in mats) or all(np.array_equal(m, mats[0]) for m in mats):
            continue  # appears or vanishes within the shutter, or still: as at the frame
        parts = [trs_of(m) for m in mats]
        if any(p is None for p in parts):
            continue
        for k in range(1, len(parts)):  # each rotation on the side of the one before: shorter arcs
            if np.dot(parts[k][1], parts[k - 1][1]) < 0:
                parts[k] = (parts[k][0], -parts[k][1], parts[k][2])
        node = gltf["nodes"][node_index]
        frame = trs_of(node_matrix(node))
        if frame is None:
            continue
        del node["matrix"]
        node["translation"], node["rotation"], node["scale"] = (
            [float(x) for x in v] for v in frame)
        for path, index, kind in (("translation", 0, "VEC3"), ("rotation", 1, "VEC4"), ("scale", 2, "VEC3")):
            output = writer.add(np.array([p[index] for p in parts], dtype=np.float32), 5126, kind)
            samplers.append({"input": input_accessor(), "output": output, "interpolation": "LINEAR"})
            channels.append({"sampler": len(samplers) - 1, "target": {"node": node_index, "path": path}})
    if channels:
        gltf["animations"] = [{"name": "motion blur", "channels": channels, "samplers": samplers}]
    return bool(channels)


def node_matrix(node):
    return np.array(node["matrix"], dtype=np.float64).reshape(4, 4).T


def mesh_arrays(mesh):
    """Per-corner positions, normals and UVs of the triangulated mesh, the triangles' corners and
    material indices, as numpy arrays (Blender 3.x and 4.x spell loop normals differently)."""
    mesh.calc_loop_triangles()
    n_tri = len(mesh.loop_triangles)
    if n_tri == 0:
        return None
    tri_loops = np.empty(n_tri * 3, dtype=np.int32)
    mesh.loop_triangles.foreach_get("loops", tri_loops)
    tri_material = np.empty(n_tri, dtype=np.int32)
    mesh.loop_triangles.foreach_get("material_index", tri_material)
    n_loops = len(mesh.loops)
    loop_vertex = np.empty(n_loops, dtype=np.int32)
    mesh.loops.foreach_get("vertex_index", loop_vertex)
    co = np.empty(len(mesh.vertices) * 3, dtype=np.float32)
    mesh.vertices.foreach_get("co", co)
    normals = np.empty(n_loops * 3, dtype=np.float32)
    if hasattr(mesh, "corner_normals"):  # Blender 4.1+
        mesh.corner_normals.foreach_get("vector", normals)
    else:
        if hasattr(mesh, "calc_normals_split"):
            mesh.calc_normals_split()
        mesh.loops.foreach_get("normal", normals)
    uv = None
    layer = next((l for l in mesh.uv_layers if l.active_render), mesh.uv_layers.active)
    if layer is not None:
        uv = np.empty(n_loops * 2, dtype=np.float32)
        layer.data.foreach_get("uv", uv)
        uv = uv.reshape(-1, 2)
        uv[:, 1] = 1.0 - uv[:, 1]  # glTF's V runs down the image
    positions = co.reshape(-1, 3)[loop_vertex]
    # Blender (x, y, z) -> glTF (x, z, -y) for positions and normals alike.
    positions = np.stack([positions[:, 0], positions[:, 2], -positions[:, 1]], axis=1)
    normals = normals.reshape(-1, 3)
    normals = np.stack([normals[:, 0], normals[:, 2], -normals[:, 1]], axis=1)
    return positions, normals, uv, tri_loops.reshape(-1, 3), tri_material


def write_mesh(writer, gltf, name, arrays, material_ids):
    """One glTF mesh, a primitive per material slot used; None when the mesh is empty."""
    positions, normals, uv, triangles, tri_material = arrays
    primitives = []
    for slot in np.unique(tri_material):
        corners = triangles[tri_material == slot].ravel()
        used, indices = np.unique(corners, return_inverse=True)
        attributes = {
            "POSITION": writer.add(positions[used].astype(np.float32), 5126, "VEC3", 34962, bounds=True),
            "NORMAL": writer.add(normals[used].astype(np.float32), 5126, "VEC3", 34962),
        }
        if uv is not None:
            attributes["TEXCOORD_0"] = writer.add(uv[used].astype(np.float32), 5126, "VEC2", 34962)
        primitive = {"attributes": attributes,
                     "indices": writer.add(indices.astype(np.uint32), 5125, "SCALAR", 34963), "mode": 4}
        slot = int(slot)
        material = material_ids[min(slot, len(material_ids) - 1)] if material_ids else None
        if material is not None:
            primitive["material"] = material
        primitives.append(primitive)
    if not primitives:
        return None
    gltf["meshes"].append({"name": name, "primitives": primitives})
    return len(gltf["meshes"]) - 1


def camera_entry(camera, width, height, export):
    """glTF's camera for Blender's camera data at this aspect ratio (sensor fit applied)."""
    aspect = width / height
    if camera.type == "ORTHO":
        fit_x = camera.sensor_fit == "HORIZONTAL" or (camera.sensor_fit == "AUTO" and aspect >= 1)
        half = camera.ortho_scale / 2
        xmag, ymag = (half, half / aspect) if fit_x else (half * aspect, half)
        return {"type": "orthographic",
                "orthographic": {"xmag": xmag, "ymag": ymag, "znear": camera.clip_start,
                                 "zfar": camera.clip_end}}
    if camera.type != "PERSP":
        export.warn("camera", f"camera type {camera.type} is rendered as a perspective camera")
    if camera.shift_x or camera.shift_y:
        export.warn("camera shift", "camera shift is not carried over (the view is centred)")
    if camera.dof.use_dof:
        export.warn("depth of field", "depth of field is not carried over (everything is in focus)")
    if camera.sensor_fit == "VERTICAL":
        yfov = 2 * math.atan(camera.sensor_height / (2 * camera.lens))
    elif camera.sensor_fit == "HORIZONTAL" or aspect >= 1:
        yfov = 2 * math.atan(camera.sensor_width / (2 * camera.lens) / aspect)
    else:
        yfov = 2 * math.atan(camera.sensor_width / (2 * camera.lens))
    return {"type": "perspective",
            "perspective": {"yfov": yfov, "aspectRatio": aspect, "znear": camera.clip_start,
                            "zfar": camera.clip_end}}


def light_entry(light, export):
    """KHR_lights_punctual's light for a Blender light; what glTF cannot carry (area lights, a
    radius, a sun angle) goes into VEACH_lights_blender on it (blender_lights.py)."""
    color = [float(c) for c in light.color]
    if not light.use_shadow:
        export.warn("light shadow", "lights without shadows are not carried over (they cast shadows)")
    if light.type == "SUN":
        entry = {"type": "directional", "color": color, "intensity": light.energy * WATTS_TO_LUMENS}
    elif light.type in ("POINT", "SPOT", "AREA"):
        # An area light's KHR light is a point of the same power: the fallback for other readers.
        entry = {"type": "point", "color": color, "intensity": light.energy * WATTS_TO_LUMENS / (4 * math.pi)}
        if light.type == "SPOT":
            outer = light.spot_size / 2
            entry["type"] = "spot"
            entry["spot"] = {"outerConeAngle": outer, "innerConeAngle": outer * (1 - light.spot_blend)}
    else:
        export.warn("light type", f"{light.type.lower()} lights are not carried over (dropped)")
        return None
    extension = blender_lights.light_extension(light)
    if extension is not None:
        entry["extensions"] = {blender_lights.EXTENSION: extension}
        if abs(extension.get("spread", math.pi) - math.pi) > 1e-3:
            export.warn("area light spread", "area light spread other than 180 degrees is rendered as 180")
    return entry


def export_frame_gltf(depsgraph, path, width=None, height=None, motion=None):
    """Writes the depsgraph's scene at its frame to path (.gltf) and path's .bin beside it;
    returns an Export. width and height (the render's) set the camera's aspect ratio. motion:
    (times, steps, shapes) for motion blur (add_motion: emissive meshes are keyed too, and the
    renderer keeps them at the frame); Export.motion says whether anything moves."""
    export = Export()
    scene = depsgraph.scene_eval if hasattr(depsgraph, "scene_eval") else depsgraph.scene
    if width is None or height is None:
        scale = scene.render.resolution_percentage / 100.0
        width = max(1, int(scene.render.resolution_x * scale))
        height = max(1, int(scene.render.resolution_y * scale))
    gltf = {"asset": {"version": "2.0", "generator": GENERATOR}, "scene": 0,
            "scenes": [{"name": scene.name, "nodes": []}], "nodes": [], "meshes": [], "materials": [],
            "cameras": [], "extensionsUsed": []}
    writer = Writer()
    converter = materials.MaterialConverter(gltf, export, os.path.dirname(os.path.abspath(path)))
    lights = []
    meshes = {}  # key -> glTF mesh index (None: empty), shared by the instances of one object
    roots = gltf["scenes"][0]["nodes"]

    def add_node(node):
        gltf["nodes"].append(node)
        roots.append(len(gltf["nodes"]) - 1)

    camera_object = scene.camera
    node_keys = []  # (node index, motion_key) of meshes and the camera, for motion blur
    frame_arrays = {}  # motion_key -> mesh_arrays written for it (objects, not instances)
    for instance in depsgraph.object_instances:
        obj = instance.object
        if not instance.is_instance and not getattr(instance, "show_self", True):
            continue
        world = matrix_array(instance.matrix_world)
        if obj.type in GEOMETRY_TYPES:
            if getattr(obj, "is_holdout", False) or getattr(obj, "is_shadow_catcher", False):
                export.warn("holdout", "holdout and shadow catcher objects are not carried over (rendered as usual)")
            if not all(getattr(obj, a, True) for a in ("visible_camera", "visible_diffuse", "visible_glossy",
                                                        "visible_transmission", "visible_shadow")):
                export.warn("ray visibility", "object ray visibility is not carried over (visible to every ray)")
        if obj.type in GEOMETRY_TYPES:
            # The evaluated object and its data: an object and its instances share one mesh.
            key = (obj.name, obj.data.as_pointer() if obj.data else 0)
            if key not in meshes:
                arrays_out = {} if motion is not None and not instance.is_instance else None
                meshes[key] = mesh_for_object(obj, writer, gltf, converter, export, arrays_out)
                if arrays_out:
                    frame_arrays[motion_key(instance)] = arrays_out["arrays"]
            if meshes[key] is not None:
                add_node({"name": obj.name, "mesh": meshes[key], "matrix": column_major(object_matrix(world))})
                node_keys.append((len(gltf["nodes"]) - 1, motion_key(instance)))
        elif obj.type == "LIGHT":
            entry = light_entry(obj.data, export)
            if entry is not None:
                area = entry.get("extensions", {}).get(blender_lights.EXTENSION, {})
                if "size" in area:
                    # The node drops scale, and Cycles scales an area light's size with its object.
                    sx, sy = (float(np.linalg.norm(world[:3, c])) for c in (0, 1))
                    area["size"] = [area["size"][0] * sx, area["size"][1] * sy]
                    if abs(sx - sy) > 1e-6 * max(sx, sy):
                        area["shape"] = {"square": "rectangle", "disk": "ellipse"}.get(area["shape"], area["shape"])
                entry["name"] = obj.name
                lights.append(entry)
                add_node({"name": obj.name, "matrix": column_major(frame_matrix(world)),
                          "extensions": {"KHR_lights_punctual": {"light": len(lights) - 1}}})
        elif obj.type == "CAMERA":
            if camera_object is not None and obj.original == camera_object.original and not instance.is_instance:
                gltf["cameras"].append(camera_entry(obj.data, width, height, export))
                export.camera_name = obj.name
                add_node({"name": obj.name, "camera": len(gltf["cameras"]) - 1,
                          "matrix": column_major(frame_matrix(world))})
                node_keys.append((len(gltf["nodes"]) - 1, motion_key(instance)))
        elif obj.type in ("CURVES", "HAIR"):
            export.warn("hair", "hair curves are not carried over (dropped)")
        elif obj.type == "VOLUME":
            export.warn("volume object", "volume objects are not carried over (dropped)")
        if obj.type == "MESH" and not instance.is_instance and any(
                p.settings.type == "HAIR" and p.settings.render_type == "PATH"
                for p in getattr(obj, "particle_systems", [])):
            export.warn("hair", "hair particles are not carried over (dropped)")
    if camera_object is None:
        export.warn("camera", "the scene has no camera")
    if motion is not None:
        export.motion = add_motion(gltf, writer, node_keys, motion, export, frame_arrays)
    if lights:
        gltf["extensions"] = {"KHR_lights_punctual": {"lights": lights}}
        gltf["extensionsUsed"].append("KHR_lights_punctual")
        if any("extensions" in entry for entry in lights):
            gltf["extensionsUsed"].append(blender_lights.EXTENSION)
    gltf["accessors"], gltf["bufferViews"] = writer.accessors, writer.views
    bin_name = os.path.splitext(os.path.basename(path))[0] + ".bin"
    gltf["buffers"] = [{"uri": bin_name, "byteLength": len(writer.blob)}]
    for key in ("meshes", "materials", "cameras", "extensionsUsed", "images", "textures", "samplers"):
        if key in gltf and not gltf[key]:
            del gltf[key]
    for hook in post_export_hooks:
        hook(gltf, depsgraph, export)
    if not writer.blob:
        gltf.pop("buffers")
        gltf.pop("accessors")
        gltf.pop("bufferViews")
    else:
        with open(os.path.join(os.path.dirname(os.path.abspath(path)), bin_name), "wb") as f:
            f.write(writer.blob)
    with open(path, "w") as f:
        json.dump(gltf, f)
    export.gltf = gltf
    return export


def mesh_for_object(obj, writer, gltf, converter, export, arrays_out=None):
    try:
        mesh = obj.to_mesh()
    except RuntimeError:
        return None
    if mesh is None:
        return None
    try:
        arrays = mesh_arrays(mesh)
        if arrays is None:
            return None
        material_ids = [converter.material(slot.material) for slot in obj.material_slots]
        if arrays_out is not None:
            arrays_out["arrays"] = arrays
        return write_mesh(writer, gltf, obj.name, arrays, material_ids)
    finally:
        obj.to_mesh_clear()

"""Building blocks for the procedural scenes in scripts/blender/scenes (Blender 3.4, bpy).

A scene module calls these from its build() and nothing else needs to know how Blender spells
things. Conventions every scene follows:
  - Blender's own units and axes (metres, Z up); the glTF exporter converts to Y up.
  - Materials are Principled BSDF, which the glTF exporter writes faithfully. A material that is
    purely diffuse (specular 0, roughness 1, not metallic, no transmission) is made with
    lambert(): it carries the custom property "lambert", and cycles_setup.lambert_materials()
    swaps it for Cycles' Diffuse BSDF in references, because Principled v1 is not exactly
    Lambertian even at specular 0 while glTF's BRDF is.
  - Images are made in memory (image_from_function); make_scene.py saves them beside the .blend
    so the .blend, the glTF and the renders all read the same file.
  - The empty factory scene has no World: the background is black unless a scene calls
    world_color() or world_hdri().
"""
import math

import bmesh
import bpy
from mathutils import Vector


def reset():
    """An empty scene: no objects, no World, factory settings."""
    bpy.ops.wm.read_factory_settings(use_empty=True)


def _link(obj):
    bpy.context.scene.collection.objects.link(obj)
    return obj


# ---------------------------------------------------------------------------------------------
# Materials

def principled(name, base_color=(0.8, 0.8, 0.8), *, metallic=0.0, roughness=0.5, specular=0.5,
               transmission=0.0, ior=1.45, alpha=1.0, emission=None, emission_strength=1.0,
               clearcoat=0.0, clearcoat_roughness=0.03, sheen_color=None, sheen_roughness=0.5,
               absorption_color=None, absorption_density=1.0, base_color_image=None, normal_image=None, normal_strength=1.0,
               roughness_image=None, blend_method=None):
    """A Principled BSDF material. Images are bpy images; base colour images are read as sRGB,
    normal and roughness images as non-colour data (as glTF defines them). roughness_image is
    read from its green channel (glTF's metallic-roughness packing) and multiplied by roughness.
    blend_method ('BLEND', 'CLIP', 'HASHED') is EEVEE's setting, which the exporter turns into
    the glTF alpha mode. sheen_color adds a Velvet BSDF (Sigma = sheen_roughness) to the
    Principled BSDF: Blender 3.4's exporter writes KHR_materials_sheen from a Velvet BSDF only,
    never from the Principled BSDF's own Sheen input. absorption_color makes a transmissive
    material's inside absorb (a Volume Absorption node, density per metre, and the thickness the
    exporter needs before it writes KHR_materials_volume)."""
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    tree = mat.node_tree
    bsdf = next(n for n in tree.nodes if n.type == 'BSDF_PRINCIPLED')
    values = {
        "Base Color": (*base_color, 1.0), "Metallic": metallic, "Roughness": roughness,
        "Specular": specular, "Transmission": transmission, "IOR": ior, "Alpha": alpha,
        "Clearcoat": clearcoat, "Clearcoat Roughness": clearcoat_roughness,
    }
    for socket, value in values.items():
        bsdf.inputs[socket].default_value = value
    if emission is not None:
        bsdf.inputs["Emission"].default_value = (*emission, 1.0)
        bsdf.inputs["Emission Strength"].default_value = emission_strength
    if base_color_image is not None:
        texture = _image_node(tree, base_color_image, 'sRGB', (-500, 300))
        tree.links.new(texture.outputs["Color"], bsdf.inputs["Base Color"])
    if normal_image is not None:
        texture = _image_node(tree, normal_image, 'Non-Color', (-700, -300))
        normal_map = tree.nodes.new("ShaderNodeNormalMap")
        normal_map.location = (-300, -300)
        normal_map.inputs["Strength"].default_value = normal_strength
        tree.links.new(texture.outputs["Color"], normal_map.inputs["Color"])
        tree.links.new(normal_map.outputs["Normal"], bsdf.inputs["Normal"])
    if roughness_image is not None:
        texture = _image_node(tree, roughness_image, 'Non-Color', (-900, 0))
        channels = tree.nodes.new("ShaderNodeSeparateColor")
        channels.location = (-600, 0)
        tree.links.new(texture.outputs["Color"], channels.inputs["Color"])
        source = channels.outputs["Green"]
        if roughness != 1.0:
            scale = tree.nodes.new("ShaderNodeMath")
            scale.operation = 'MULTIPLY'
            scale.inputs[1].default_value = roughness
            tree.links.new(source, scale.inputs[0])
            source = scale.outputs[0]
        tree.links.new(source, bsdf.inputs["Roughness"])
    if sheen_color is not None:
        velvet = tree.nodes.new("ShaderNodeBsdfVelvet")
        velvet.inputs["Color"].default_value = (*sheen_color, 1.0)
        velvet.inputs["Sigma"].default_value = sheen_roughness
        both = tree.nodes.new("ShaderNodeAddShader")
        output = next(n for n in tree.nodes if n.type == 'OUTPUT_MATERIAL')
        tree.links.new(bsdf.outputs[0], both.inputs[0])
        tree.links.new(velvet.outputs[0], both.inputs[1])
        tree.links.new(both.outputs[0], output.inputs["Surface"])
    if absorption_color is not None:
        _absorbing_volume(tree, absorption_color, absorption_density)
    if blend_method is not None:
        mat.blend_method = blend_method
    return mat


def _absorbing_volume(tree, color, density):
    output = next(n for n in tree.nodes if n.type == 'OUTPUT_MATERIAL')
    volume = tree.nodes.new("ShaderNodeVolumeAbsorption")
    volume.inputs["Color"].default_value = (*color, 1.0)
    volume.inputs["Density"].default_value = density
    tree.links.new(volume.outputs[0], output.inputs["Volume"])
    # The exporter reads the thickness from a node group named "glTF Settings" (its own add-on
    # makes it); without a thickness above 0 it writes no volume at all.
    group = bpy.data.node_groups.get("glTF Settings")
    if group is None:
        group = bpy.data.node_groups.new("glTF Settings", "ShaderNodeTree")
        group.inputs.new("NodeSocketFloat", "Thickness")
    settings = tree.nodes.new("ShaderNodeGroup")
    settings.node_tree = group
    settings.inputs["Thickness"].default_value = 1.0


def lambert(name, color, *, image=None, normal_image=None):
    """A purely diffuse material (tagged "lambert": exactly Lambertian in glTF and in the Cycles
    reference), optionally with a tangent-space normal map (a Non-Color image, strength 1)."""
    mat = principled(name, color, roughness=1.0, specular=0.0, base_color_image=image, normal_image=normal_image)
    mat["lambert"] = True
    return mat


def emitter(name, color, strength):
    """A black diffuse surface emitting color x strength (W/(m² sr) per unit colour, as Blender's
    Emission Strength; the exporter writes KHR_materials_emissive_strength)."""
    mat = principled(name, (0.0, 0.0, 0.0), roughness=1.0, specular=0.0, emission=color,
                     emission_strength=strength)
    mat["lambert"] = True
    return mat


def _image_node(tree, image, colorspace, location):
    if image.colorspace_settings.name != colorspace:
        raise ValueError("image %s is %s, this input reads %s: make it with colorspace='%s'"
                         % (image.name, image.colorspace_settings.name, colorspace, colorspace))
    node = tree.nodes.new("ShaderNodeTexImage")
    node.image = image
    node.location = location
    return node


# ---------------------------------------------------------------------------------------------
# Images

def image_from_function(name, width, height, texel, *, float_buffer=False, file_format='PNG', colorspace=None):
    """An image whose texel (i, j) -> (r, g, b) comes from texel(), with (0, 0) the texel at UV
    (0, 0), Blender's bottom-left (glTF's V runs the other way; the exporter flips it). Values
    are stored as they are: encoded sRGB for a colour PNG, linear for a float image.
    colorspace: 'sRGB' (default for 8-bit), 'Linear' (default for float), or 'Non-Color' for
    data (normal, roughness maps)."""
    pixels = []
    for j in range(height):
        for i in range(width):
            pixels.extend((*texel(i, j), 1.0))
    return image_from_pixels(name, width, height, pixels, float_buffer=float_buffer, file_format=file_format,
                             colorspace=colorspace)


def image_from_pixels(name, width, height, rgba, *, float_buffer=False, file_format='PNG', colorspace=None):
    """An image from a flat RGBA sequence (or numpy array) in Blender's order: rows bottom-up."""
    image = bpy.data.images.new(name, width, height, float_buffer=float_buffer, alpha=False)
    # The colour space first: changing it later regenerates a generated image, losing its pixels.
    image.colorspace_settings.name = colorspace or ('Linear' if float_buffer else 'sRGB')
    image.pixels.foreach_set(rgba)
    image.file_format = file_format
    return image


# ---------------------------------------------------------------------------------------------
# Geometry

def mesh(name, vertices, faces, material, *, uvs=None, smooth=False):
    """A mesh object from vertex positions and faces (tuples of vertex indices, counter-clockwise
    seen from the front). uvs, when given, is one (u, v) per face corner, in face order."""
    data = bpy.data.meshes.new(name)
    data.from_pydata(vertices, [], faces)
    if uvs is not None:
        layer = data.uv_layers.new(name="UVMap")
        for loop, uv in zip(data.loops, uvs):
            layer.data[loop.index].uv = uv
    for polygon in data.polygons:
        polygon.use_smooth = smooth
    data.update()
    data.materials.append(material)
    return _link(bpy.data.objects.new(name, data))


def quad(name, a, b, c, d, material, *, uv=False):
    """A quad a-b-c-d (front side counter-clockwise); with uv, the unit square mapped a=(0,0),
    b=(1,0), c=(1,1), d=(0,1)."""
    uvs = [(0, 0), (1, 0), (1, 1), (0, 1)] if uv else None
    return mesh(name, [a, b, c, d], [(0, 1, 2, 3)], material, uvs=uvs)


def sliced_bar(name, location, height, half_width, slices, material):
    """An upright square bar (2 half_width wide, standing on location) cut into slices along its
    height, so that an armature bends it smoothly at its joints."""
    vertices, faces = [], []
    for k in range(slices + 1):
        z = height * k / slices
        vertices += [(x, y, z) for x, y in ((-half_width, -half_width), (half_width, -half_width),
                                            (half_width, half_width), (-half_width, half_width))]
    for k in range(slices):
        a, b = 4 * k, 4 * (k + 1)
        faces += [(a + i, a + (i + 1) % 4, b + (i + 1) % 4, b + i) for i in range(4)]
    faces += [(3, 2, 1, 0), (b, b + 1, b + 2, b + 3)]
    bar = mesh(name, vertices, faces, material)
    bar.location = location
    return bar


def box(name, center, size, rotation_z_degrees, material, *, uv=False):
    """An axis-aligned unit cube scaled to size (x, y, z), turned about Z, centred at center;
    with uv, each face gets its own UV square."""
    data = bpy.data.meshes.new(name)
    builder = bmesh.new()
    if uv:
        builder.loops.layers.uv.new("UVMap")
    bmesh.ops.create_cube(builder, size=1.0, calc_uvs=uv)
    builder.to_mesh(data)
    builder.free()
    data.materials.append(material)
    obj = _link(bpy.data.objects.new(name, data))
    obj.location = center
    obj.scale = size
    obj.rotation_euler = (0.0, 0.0, math.radians(rotation_z_degrees))
    return obj


def uv_sphere(name, center, radius, material, *, segments=48, rings=24, smooth=True):
    """A UV sphere (with UVs) of segments x rings, smooth-shaded unless told otherwise."""
    data = bpy.data.meshes.new(name)
    builder = bmesh.new()
    builder.loops.layers.uv.new("UVMap")  # calc_uvs fills an existing layer only
    bmesh.ops.create_uvsphere(builder, u_segments=segments, v_segments=rings, radius=radius, calc_uvs=True)
    builder.to_mesh(data)
    builder.free()
    for polygon in data.polygons:
        polygon.use_smooth = smooth
    data.materials.append(material)
    obj = _link(bpy.data.objects.new(name, data))
    obj.location = center
    return obj


def grid(name, size, subdivisions, material, *, location=(0.0, 0.0, 0.0)):
    """A flat size x size square in the XY plane, subdivided, with UVs over the unit square."""
    data = bpy.data.meshes.new(name)
    builder = bmesh.new()
    builder.loops.layers.uv.new("UVMap")
    bmesh.ops.create_grid(builder, x_segments=subdivisions, y_segments=subdivisions, size=size / 2, calc_uvs=True)
    builder.to_mesh(data)
    builder.free()
    data.materials.append(material)
    obj = _link(bpy.data.objects.new(name, data))
    obj.location = location
    return obj


# ---------------------------------------------------------------------------------------------
# Camera, lights, World

def aim(obj, target):
    """Turn obj (a camera or light, which look along their local -Z) towards target."""
    direction = Vector(target) - Vector(obj.location)
    obj.rotation_euler = direction.to_track_quat('-Z', 'Y').to_euler()


def camera(location, target, *, lens=35.0, name="Camera"):
    """A perspective camera looking at target with a focal length in mm (36 mm sensor, fit to the
    longer side of the render), made the scene's camera."""
    data = bpy.data.cameras.new(name)
    data.lens = lens
    data.sensor_fit = 'AUTO'
    obj = _link(bpy.data.objects.new(name, data))
    obj.location = location
    aim(obj, target)
    bpy.context.scene.camera = obj
    return obj


def _light(kind, name, location, power, color):
    data = bpy.data.lights.new(name, kind)
    data.energy = power
    data.color = color
    obj = _link(bpy.data.objects.new(name, data))
    obj.location = location
    return obj


def point_light(name, location, power, *, color=(1, 1, 1), radius=0.0):
    """Blender point light: power in W, radius the emitting sphere's (0: a true point)."""
    obj = _light('POINT', name, location, power, color)
    obj.data.shadow_soft_size = radius
    return obj


def spot_light(name, location, power, *, target=None, rotation=None, color=(1, 1, 1), size_degrees=45.0,
               blend=0.15, radius=0.0):
    """Blender spot light aimed at target (or given an Euler rotation in degrees): power in W
    (as if it radiated in every direction), size the full cone angle."""
    obj = _light('SPOT', name, location, power, color)
    obj.data.spot_size = math.radians(size_degrees)
    obj.data.spot_blend = blend
    obj.data.shadow_soft_size = radius
    _orient(obj, target, rotation)
    return obj


def sun_light(name, strength, *, target=None, rotation=None, location=(0, 0, 5), color=(1, 1, 1),
              angle_degrees=0.0):
    """Blender sun: strength in W/m² (irradiance), shining along its local -Z, angle the disc's
    angular diameter (0: hard shadows)."""
    obj = _light('SUN', name, location, strength, color)
    obj.data.angle = math.radians(angle_degrees)
    _orient(obj, target, rotation)
    return obj


def area_light(name, location, power, *, target=None, rotation=None, color=(1, 1, 1), shape='SQUARE',
               size=1.0, size_y=None):
    """Blender area light: power in W, shape SQUARE, RECTANGLE, DISK or ELLIPSE, size (and
    size_y for RECTANGLE/ELLIPSE) in metres. Blender 3.4's glTF exporter does not write area
    lights (KHR_lights_punctual has none)."""
    obj = _light('AREA', name, location, power, color)
    obj.data.shape = shape
    obj.data.size = size
    if size_y is not None:
        obj.data.size_y = size_y
    _orient(obj, target, rotation)
    return obj


def _orient(obj, target, rotation):
    if target is not None:
        aim(obj, target)
    elif rotation is not None:
        obj.rotation_euler = tuple(math.radians(a) for a in rotation)


def _world():
    scene = bpy.context.scene
    if scene.world is None:
        scene.world = bpy.data.worlds.new("World")
    scene.world.use_nodes = True
    return scene.world.node_tree


def world_color(color, strength=1.0):
    """A uniform World (radiance color x strength). glTF carries no World: render with
    `veach --env-color` to match."""
    tree = _world()
    background = tree.nodes["Background"]
    background.inputs["Color"].default_value = (*color, 1.0)
    background.inputs["Strength"].default_value = strength


def world_hdri(image, strength=1.0, rotation_z_degrees=0.0):
    """An equirectangular World image (Blender's mapping, as `veach --env` reads it). glTF carries
    no World: render with `veach --env FILE --env-strength S --env-rotate DEGREES` to match."""
    tree = _world()
    background = tree.nodes["Background"]
    background.inputs["Strength"].default_value = strength
    texture = tree.nodes.new("ShaderNodeTexEnvironment")
    texture.image = image
    texture.location = (-300, 300)
    tree.links.new(texture.outputs["Color"], background.inputs["Color"])
    if rotation_z_degrees:
        coordinates = tree.nodes.new("ShaderNodeTexCoord")
        mapping = tree.nodes.new("ShaderNodeMapping")
        mapping.inputs["Rotation"].default_value[2] = math.radians(rotation_z_degrees)
        tree.links.new(coordinates.outputs["Generated"], mapping.inputs["Vector"])
        tree.links.new(mapping.outputs["Vector"], texture.inputs["Vector"])


# ---------------------------------------------------------------------------------------------
# Animation

def frame_range(first, last, fps=24):
    scene = bpy.context.scene
    scene.frame_start, scene.frame_end = first, last
    scene.render.fps = fps


def keyframes(owner, data_path, values, *, interpolation='LINEAR'):
    """Key owner.data_path (an object's "location", a shape key's "value", ...) at each
    {frame: value} and set the interpolation of the keys made."""
    for frame, value in sorted(values.items()):
        setattr(owner, data_path, value)
        owner.keyframe_insert(data_path, frame=frame)
    action = owner.id_data.animation_data.action
    for curve in action.fcurves:
        for point in curve.keyframe_points:
            point.interpolation = interpolation


def shape_key(obj, name, offset):
    """A shape key whose vertex k moves by offset(k, position) (a Vector); adds the basis first."""
    if obj.data.shape_keys is None:
        obj.shape_key_add(name="Basis", from_mix=False)
    key = obj.shape_key_add(name=name, from_mix=False)
    for k, vertex in enumerate(obj.data.vertices):
        key.data[k].co = vertex.co + Vector(offset(k, vertex.co))
    return key


def bone_chain(name, mesh_object, joints):
    """An armature of bones joint[0]->joint[1]->... (bone k is named "bone<k>"), deforming
    mesh_object through an Armature modifier: each vertex follows the bone whose segment is
    nearest, so a pose bends the mesh at the joints. Returns the armature object; pose it with
    keyframes(obj.pose.bones["bone1"], "rotation_euler", {...})."""
    data = bpy.data.armatures.new(name)
    rig = _link(bpy.data.objects.new(name, data))
    bpy.context.view_layer.objects.active = rig
    bpy.ops.object.mode_set(mode='EDIT')
    parent = None
    for k in range(len(joints) - 1):
        bone = data.edit_bones.new("bone%d" % k)
        bone.head, bone.tail = Vector(joints[k]), Vector(joints[k + 1])
        if parent is not None:
            bone.parent, bone.use_connect = parent, True
        parent = bone
    bpy.ops.object.mode_set(mode='OBJECT')
    segments = [(Vector(joints[k]), Vector(joints[k + 1])) for k in range(len(joints) - 1)]
    groups = [mesh_object.vertex_groups.new(name="bone%d" % k) for k in range(len(segments))]
    world = mesh_object.matrix_world
    for vertex in mesh_object.data.vertices:
        p = world @ vertex.co
        distances = []
        for a, b in segments:
            t = max(0.0, min(1.0, (p - a).dot(b - a) / (b - a).length_squared))
            distances.append((p - (a + t * (b - a))).length)
        groups[distances.index(min(distances))].add([vertex.index], 1.0, 'REPLACE')
    modifier = mesh_object.modifiers.new("Armature", 'ARMATURE')
    modifier.object = rig
    for bone in rig.pose.bones:
        bone.rotation_mode = 'XYZ'
    return rig


def is_animated():
    """True when anything in the file is keyed (objects, shape keys, materials, lights, World)."""
    collections = (bpy.data.objects, bpy.data.shape_keys, bpy.data.materials, bpy.data.lights,
                   bpy.data.cameras, bpy.data.worlds, bpy.data.armatures)
    return any(item.animation_data is not None and item.animation_data.action is not None
               for collection in collections for item in collection)

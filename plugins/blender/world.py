# Blender's World as libveach's environment scene options (env_color, env_map, env_strength,
# env_rotate): glTF carries no World, so the add-on passes it beside the glTF.
#
# Carried exactly: no World (black, as Cycles renders it), a World without nodes (its colour), and
# a Background shader whose Color is a uniform colour or an equirectangular Environment Texture,
# optionally behind a Mapping node that rotates about Z (Blender's up; the library's env_rotate
# is that angle), with the Background's Strength. Any other tree is reported, naming what was
# dropped, and rendered with its best uniform stand-in: the Background's colour when only its
# Color input is unusable, else the World's viewport colour.
import math

from . import materials


def linked(s):
    return materials.linked_from(s)[0]


def uniform(color, strength=1.0):
    return {"env_color": ",".join("%.9g" % max(0.0, float(c)) for c in color[:3]), "env_strength": float(strength)}


def environment_options(world, export, out_dir):
    """The scene options for the World (an empty dict: no environment, black)."""
    if world is None:
        return {}
    if not world.use_nodes or world.node_tree is None:
        return uniform(world.color)
    tree = world.node_tree
    outputs = [n for n in tree.nodes if n.type == "OUTPUT_WORLD"]
    output = next((n for n in outputs if n.is_active_output), outputs[0] if outputs else None)
    if output is None:
        return {}
    surface = linked(output.inputs["Surface"])
    if surface is None:
        return {}
    if surface.type != "BACKGROUND":
        export.warn("world", f"World shader '{surface.bl_label}' is not carried over: rendered as the World's "
                             "viewport colour")
        return uniform(world.color)
    strength_socket = surface.inputs["Strength"]
    if strength_socket.is_linked:
        export.warn("world", "a link into the World's Background Strength is dropped (its own value is used)")
    strength = float(strength_socket.default_value)
    color_socket = surface.inputs["Color"]
    source = linked(color_socket)
    if source is None:
        return uniform(color_socket.default_value, strength)
    if source.type != "TEX_ENVIRONMENT":
        export.warn("world", f"World node '{source.bl_label}' into the Background colour is not carried over: "
                             "rendered as the Background's own colour")
        return uniform(color_socket.default_value, strength)
    if source.image is None:
        export.warn("world", "the World's Environment Texture has no image: rendered as the Background's colour")
        return uniform(color_socket.default_value, strength)
    if source.projection != "EQUIRECTANGULAR":
        export.warn("world", f"{source.projection.lower()} environment projection is not carried over: rendered "
                             "as the World's viewport colour")
        return uniform(world.color)
    path = materials.image_file(source.image, out_dir, export)
    if path is None:
        return uniform(world.color)
    options = {"env_map": path, "env_strength": strength}
    rotation = mapping_rotation(linked(source.inputs["Vector"]), export)
    if rotation:
        options["env_rotate"] = rotation
    return options


def mapping_rotation(node, export):
    """Degrees about Z of the Mapping node feeding the Environment Texture (0 for none)."""
    if node is None:
        return 0.0
    if node.type != "MAPPING":
        if node.type != "TEX_COORD":
            export.warn("world", f"World node '{node.bl_label}' into the environment's vector is dropped")
        return 0.0
    inputs = node.inputs
    dropped = []
    if any(s.is_linked for s in inputs[1:]):
        dropped.append("linked inputs")
    location, rotation, scale = (inputs.get(n) for n in ("Location", "Rotation", "Scale"))
    # Location is left alone: moving an infinitely far environment changes no direction.
    if rotation is None:
        return 0.0
    rx, ry, rz = rotation.default_value
    if abs(rx) > 1e-6 or abs(ry) > 1e-6:
        dropped.append("rotation about X or Y")
    if scale is not None and any(abs(v - 1.0) > 1e-6 for v in scale.default_value):
        dropped.append("scale")
    source = linked(inputs["Vector"])
    if source is not None and source.type != "TEX_COORD":
        dropped.append(f"'{source.bl_label}' coordinates")
    if dropped:
        export.warn("world", "the World Mapping node's " + ", ".join(dropped) + " not carried over")
    degrees = math.degrees(rz)
    # A Texture-type mapping rotates the coordinates, i.e. the environment the other way.
    return -degrees if node.vector_type == "TEXTURE" else degrees

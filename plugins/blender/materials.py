# Blender materials as glTF materials (metallic-roughness plus the KHR_materials_* extensions
# libveach reads), for gltf_export.py.
#
# The surface shader connected to the active Material Output decides: a Principled BSDF maps
# input by input; Diffuse (exactly Lambertian: specular 0), Glossy (metal), Glass and Emission
# map to the glTF material that renders as they do; a Principled BSDF + Velvet BSDF sum is sheen.
# An Image Texture linked straight into a colour, roughness/metallic (or through Separate Colour's
# green/blue), emission, alpha or Normal Map input becomes a texture. Anything else linked into an
# input (procedural textures, maths, ramps, groups) is dropped: the input's own value is used and
# one warning per kind says so, as for SSS, anisotropy, displacement and volumes that glTF cannot
# carry. Principled v1's Specular sets F0 = 0.08 * specular for reflection while its IOR only
# bends transmission; glTF's F0 comes from the IOR times KHR_materials_specular's colour, so that
# colour is 0.08 * specular / F0(ior).
import math
import os

import bpy

PROCEDURAL = {"TEX_NOISE", "TEX_VORONOI", "TEX_WAVE", "TEX_MUSGRAVE", "TEX_CHECKER", "TEX_BRICK",
              "TEX_GRADIENT", "TEX_MAGIC", "TEX_SKY", "TEX_WHITE_NOISE", "TEX_POINTDENSITY", "TEX_IES"}
DEFAULT_COLOR = (0.8, 0.8, 0.8)  # Cycles' surface for an empty material slot


def socket(node, *names):
    """The first input of node with one of names (Blender 3.x and 4.x name some differently)."""
    for name in names:
        s = node.inputs.get(name)
        if s is not None:
            return s
    return None


def linked_from(s):
    """The (node, output socket) feeding input s through reroutes, or (None, None)."""
    if s is None or not s.is_linked:
        return None, None
    link = s.links[0]
    while link.from_node.type == "REROUTE":
        if not link.from_node.inputs[0].is_linked:
            return None, None
        link = link.from_node.inputs[0].links[0]
    return link.from_node, link.from_socket


def f0_of_ior(ior):
    return ((ior - 1.0) / (ior + 1.0)) ** 2


def image_file(image, out_dir, export):
    """A file path libveach can open for the image: the file itself (absolute), or the packed
    bytes written into out_dir; None (warned about) when there is no file."""
    if image.packed_file is not None:
        extension = os.path.splitext(image.filepath)[1] or "." + image.file_format.lower()
        path = os.path.join(out_dir, "packed_%x%s" % (image.as_pointer(), extension))
        if not os.path.exists(path):
            with open(path, "wb") as f:
                f.write(image.packed_file.data)
        return path
    if image.source != "FILE":
        export.warn("generated image", f"image '{image.name}' is {image.source.lower()}, not a file "
                                       "(dropped: save or pack it)")
        return None
    path = os.path.normpath(bpy.path.abspath(image.filepath_raw or image.filepath, library=image.library))
    if not os.path.isfile(path):
        export.warn("missing image", f"image file '{path}' is missing (dropped)")
        return None
    return path


class MaterialConverter:
    def __init__(self, gltf, export, out_dir):
        self.gltf = gltf
        self.export = export
        self.out_dir = out_dir
        self.by_material = {}
        self.images = {}
        self.textures = {}
        self.default = None
        self.reported_images = set()  # Image Texture nodes whose image was dropped (warned once)

    def use_extension(self, name):
        if name not in self.gltf["extensionsUsed"]:
            self.gltf["extensionsUsed"].append(name)

    def add(self, entry):
        self.gltf["materials"].append(entry)
        return len(self.gltf["materials"]) - 1

    def material(self, material):
        """The glTF material index for a Blender material (None: Cycles' default grey)."""
        if material is None:
            if self.default is None:
                self.default = self.add(self.lambert_entry("default", DEFAULT_COLOR))
            return self.default
        key = material.name
        if key not in self.by_material:
            self.by_material[key] = self.add(self.convert(material))
        return self.by_material[key]

    def lambert_entry(self, name, color):
        self.use_extension("KHR_materials_specular")
        return {"name": name, "doubleSided": True,
                "pbrMetallicRoughness": {"baseColorFactor": [*color[:3], 1.0], "metallicFactor": 0.0,
                                         "roughnessFactor": 1.0},
                "extensions": {"KHR_materials_specular": {"specularFactor": 0.0}}}

    # -- values and textures ------------------------------------------------------------------

    def value(self, s, what):
        """The input's own value; a link into it that is not carried over is warned about."""
        node, _ = linked_from(s)
        if node is not None and node not in self.reported_images:
            self.warn_node(node, what)
        return s.default_value

    def warn_node(self, node, what):
        if node.type in PROCEDURAL:
            self.export.warn("procedural texture",
                             f"procedural textures are not carried over ({node.bl_label} into {what}: "
                             "the input's own value is used)")
        elif node.type == "GROUP":
            self.export.warn("node group", f"node groups in materials are not carried over ({what})")
        else:
            self.export.warn(f"node {node.type}",
                             f"material node '{node.bl_label}' is not carried over ({what}: the input's own value "
                             "is used)")

    def texture(self, s, what, channel=None):
        """{"index": ...} for an Image Texture linked into s (through Separate Colour's channel when
        channel is given), else None (warned about when something else is linked)."""
        node, out = linked_from(s)
        if node is None:
            return None
        if channel is not None and node.type in ("SEPARATE_COLOR", "SEPRGB"):
            if out.name not in channel:
                self.export.warn("texture channel", f"a texture channel other than glTF's is used for {what} "
                                                    "(dropped)")
                return None
            node, out = linked_from(node.inputs[0])
            if node is None:
                return None
        if node.type != "TEX_IMAGE":
            self.warn_node(node, what)
            return None
        index = self.image_texture(node, what)
        if index is None:
            self.reported_images.add(node)
            return None
        return {"index": index}

    def image_texture(self, node, what):
        image = node.image
        if image is None:
            return None
        vector, _ = linked_from(node.inputs.get("Vector"))
        if vector is not None and vector.type != "UVMAP":
            self.export.warn("texture mapping",
                             f"texture coordinates other than the UV map are not carried over ({vector.bl_label})")
        uri = self.image_uri(image)
        if uri is None:
            return None
        if image.name not in self.images:
            self.gltf.setdefault("images", []).append({"uri": uri, "name": image.name})
            self.images[image.name] = len(self.gltf["images"]) - 1
        nearest = node.interpolation == "Closest"
        wrap = 10497 if node.extension == "REPEAT" else 33071
        key = (image.name, nearest, wrap)
        if key not in self.textures:
            samplers = self.gltf.setdefault("samplers", [])
            samplers.append({"magFilter": 9728 if nearest else 9729, "minFilter": 9728 if nearest else 9987,
                             "wrapS": wrap, "wrapT": wrap})
            self.gltf.setdefault("textures", []).append({"source": self.images[image.name],
                                                         "sampler": len(samplers) - 1})
            self.textures[key] = len(self.gltf["textures"]) - 1
        return self.textures[key]

    def image_uri(self, image):
        return image_file(image, self.out_dir, self.export)

    # -- shaders ------------------------------------------------------------------------------

    def convert(self, material):
        entry = {"name": material.name, "doubleSided": not material.use_backface_culling}
        if material.get("lambert"):
            entry["extras"] = {"lambert": 1}
        if not material.use_nodes or material.node_tree is None:
            entry.update(self.lambert_entry(material.name, material.diffuse_color))
            entry["doubleSided"] = not material.use_backface_culling
            return entry
        tree = material.node_tree
        output = next((n for n in tree.nodes if n.type == "OUTPUT_MATERIAL" and n.is_active_output), None)
        output = output or next((n for n in tree.nodes if n.type == "OUTPUT_MATERIAL"), None)
        if output is None:
            entry.update(self.lambert_entry(material.name, (0, 0, 0)))
            return entry
        if output.inputs["Displacement"].is_linked:
            self.export.warn("displacement", "material displacement is not carried over")
        self.volume(output, entry)
        node, _ = linked_from(output.inputs["Surface"])
        self.surface(node, entry)
        if not entry.get("extensions"):
            entry.pop("extensions", None)
        return entry

    def surface(self, node, entry):
        pbr = entry.setdefault("pbrMetallicRoughness", {})
        ext = entry.setdefault("extensions", {})
        if node is None:  # no surface: black, as Cycles renders it
            pbr.update({"baseColorFactor": [0, 0, 0, 1], "metallicFactor": 0.0})
            return
        kind = node.type
        if kind == "BSDF_PRINCIPLED":
            self.principled(node, entry)
        elif kind == "ADD_SHADER" and {linked_from(s)[0].type for s in node.inputs if s.is_linked} == {
                "BSDF_PRINCIPLED", "BSDF_VELVET"}:
            nodes = [linked_from(s)[0] for s in node.inputs]
            self.principled(next(n for n in nodes if n.type == "BSDF_PRINCIPLED"), entry)
            velvet = next(n for n in nodes if n.type == "BSDF_VELVET")
            ext["KHR_materials_sheen"] = {"sheenColorFactor": list(self.value(velvet.inputs["Color"], "sheen")[:3]),
                                          "sheenRoughnessFactor": float(self.value(velvet.inputs["Sigma"], "sheen"))}
            self.use_extension("KHR_materials_sheen")
        elif kind == "BSDF_DIFFUSE":
            self.base_color(node.inputs["Color"], pbr, 1.0)
            pbr.update({"metallicFactor": 0.0, "roughnessFactor": 1.0})
            ext["KHR_materials_specular"] = {"specularFactor": 0.0}
            self.use_extension("KHR_materials_specular")
            if self.value(node.inputs["Roughness"], "roughness") > 0:
                self.export.warn("oren-nayar", "Diffuse BSDF roughness (Oren-Nayar) is rendered as Lambertian")
        elif kind == "BSDF_GLOSSY" or kind == "BSDF_ANISOTROPIC":
            self.base_color(node.inputs["Color"], pbr, 1.0)
            pbr.update({"metallicFactor": 1.0, "roughnessFactor": float(self.value(node.inputs["Roughness"],
                                                                                   "roughness"))})
        elif kind == "BSDF_GLASS" or kind == "BSDF_REFRACTION":
            self.base_color(node.inputs["Color"], pbr, 1.0)
            pbr.update({"metallicFactor": 0.0, "roughnessFactor": float(self.value(node.inputs["Roughness"],
                                                                                   "roughness"))})
            ext["KHR_materials_transmission"] = {"transmissionFactor": 1.0}
            ext["KHR_materials_ior"] = {"ior": float(self.value(node.inputs["IOR"], "IOR"))}
            self.use_extension("KHR_materials_transmission")
            self.use_extension("KHR_materials_ior")
        elif kind == "EMISSION":
            pbr.update({"baseColorFactor": [0, 0, 0, 1], "metallicFactor": 0.0})
            self.emission(node.inputs["Color"], node.inputs["Strength"], entry)
        elif kind == "BSDF_TRANSPARENT":
            pbr.update({"baseColorFactor": [0, 0, 0, 0], "metallicFactor": 0.0})
            entry["alphaMode"] = "BLEND"
        else:
            if kind == "SUBSURFACE_SCATTERING":
                self.export.warn("subsurface scattering", "subsurface scattering is not carried over (diffuse)")
            else:
                self.export.warn(f"shader {kind}", f"shader '{node.bl_label}' is not carried over "
                                                   "(approximated by a diffuse surface of its colour)")
            color = socket(node, "Color", "Base Color")
            if color is None and kind in ("MIX_SHADER", "ADD_SHADER"):
                # The first shader of the mix stands for it.
                inner = next((linked_from(s)[0] for s in node.inputs if s.is_linked and s.type == "SHADER"), None)
                entry.pop("pbrMetallicRoughness")
                entry.pop("extensions")
                return self.surface(inner, entry)
            self.base_color(color, pbr, 1.0) if color is not None else pbr.update(
                {"baseColorFactor": [*DEFAULT_COLOR, 1]})
            pbr.update({"metallicFactor": 0.0, "roughnessFactor": 1.0})
            ext["KHR_materials_specular"] = {"specularFactor": 0.0}
            self.use_extension("KHR_materials_specular")

    def base_color(self, s, pbr, alpha):
        texture = self.texture(s, "base color")
        if texture is not None:
            pbr["baseColorTexture"] = texture
            pbr["baseColorFactor"] = [1.0, 1.0, 1.0, alpha]
        else:
            pbr["baseColorFactor"] = [*[float(c) for c in self.value(s, "base color")[:3]], alpha]

    def emission(self, color_socket, strength_socket, entry):
        strength = float(self.value(strength_socket, "emission strength"))
        texture = self.texture(color_socket, "emission")
        if texture is not None:
            entry["emissiveTexture"] = texture
            color = [1.0, 1.0, 1.0]
        else:
            color = [float(c) for c in self.value(color_socket, "emission")[:3]]
        if strength <= 0 or max(color) <= 0:
            return
        entry["emissiveFactor"] = color
        if strength != 1.0:
            entry.setdefault("extensions", {})["KHR_materials_emissive_strength"] = {"emissiveStrength": strength}
            self.use_extension("KHR_materials_emissive_strength")

    def principled(self, node, entry):
        pbr = entry.setdefault("pbrMetallicRoughness", {})
        ext = entry.setdefault("extensions", {})
        alpha_socket = socket(node, "Alpha")
        alpha_node, alpha_out = linked_from(alpha_socket)
        alpha = float(alpha_socket.default_value) if alpha_node is None else 1.0
        self.base_color(socket(node, "Base Color"), pbr, alpha)
        if alpha_node is not None:
            color_node, _ = linked_from(socket(node, "Base Color"))
            if alpha_node.type == "TEX_IMAGE" and alpha_out.name == "Alpha" and color_node == alpha_node:
                entry["alphaMode"] = "BLEND"
            else:
                self.export.warn("alpha", "an alpha input other than the base colour image's alpha is dropped")
        elif alpha < 1.0:
            entry["alphaMode"] = "BLEND"  # Cycles blends whatever the EEVEE blend mode says

        metallic_s, roughness_s = socket(node, "Metallic"), socket(node, "Roughness")
        rough_tex = self.texture(roughness_s, "roughness", channel=("Green", "G")) if roughness_s.is_linked else None
        metal_tex = self.texture(metallic_s, "metallic", channel=("Blue", "B")) if metallic_s.is_linked else None
        pbr["metallicFactor"] = 1.0 if metal_tex else float(metallic_s.default_value)
        pbr["roughnessFactor"] = 1.0 if rough_tex else float(roughness_s.default_value)
        if rough_tex or metal_tex:
            if rough_tex and metal_tex and rough_tex["index"] != metal_tex["index"]:
                self.export.warn("texture channel", "roughness and metallic from different images: metallic's dropped")
                metal_tex = None
                pbr["metallicFactor"] = float(metallic_s.default_value)
            pbr["metallicRoughnessTexture"] = rough_tex or metal_tex
            if not metal_tex:
                pbr["metallicFactor"] = float(metallic_s.default_value)
            if not rough_tex:
                pbr["roughnessFactor"] = float(roughness_s.default_value)

        ior = float(self.value(socket(node, "IOR"), "IOR"))
        ext["KHR_materials_ior"] = {"ior": ior}
        self.use_extension("KHR_materials_ior")
        specular = float(self.value(socket(node, "Specular", "Specular IOR Level"), "specular"))
        if socket(node, "Specular IOR Level") is not None:
            specular_color = 2.0 * specular  # 4.x: 0.5 means F0 from the IOR
        else:
            specular_color = 0.08 * specular / max(f0_of_ior(ior), 1e-6)
        if abs(specular_color - 1.0) > 1e-4:
            ext["KHR_materials_specular"] = {"specularColorFactor": [specular_color] * 3}
            self.use_extension("KHR_materials_specular")
        transmission = float(self.value(socket(node, "Transmission", "Transmission Weight"), "transmission"))
        if transmission > 0:
            ext["KHR_materials_transmission"] = {"transmissionFactor": transmission}
            self.use_extension("KHR_materials_transmission")
        clearcoat = float(self.value(socket(node, "Clearcoat", "Coat Weight"), "clearcoat"))
        if clearcoat > 0:
            ext["KHR_materials_clearcoat"] = {
                "clearcoatFactor": clearcoat,
                "clearcoatRoughnessFactor": float(self.value(socket(node, "Clearcoat Roughness", "Coat Roughness"),
                                                             "clearcoat roughness"))}
            self.use_extension("KHR_materials_clearcoat")
        subsurface = socket(node, "Subsurface", "Subsurface Weight")
        if subsurface is not None and (subsurface.is_linked or subsurface.default_value > 0):
            self.export.warn("subsurface scattering", "subsurface scattering is not carried over (diffuse)")
        sheen = socket(node, "Sheen", "Sheen Weight")
        if sheen is not None and (sheen.is_linked or sheen.default_value > 0):
            self.export.warn("sheen", "Principled sheen is not carried over (a Velvet BSDF added to it is)")
        aniso = socket(node, "Anisotropic")
        if aniso is not None and (aniso.is_linked or aniso.default_value > 0):
            self.export.warn("anisotropy", "anisotropic roughness is not carried over (isotropic)")
        self.emission(socket(node, "Emission", "Emission Color"), socket(node, "Emission Strength"), entry)
        normal = self.normal_map(socket(node, "Normal"))
        if normal is not None:
            entry["normalTexture"] = normal

    def normal_map(self, s):
        node, _ = linked_from(s)
        if node is None:
            return None
        if node.type != "NORMAL_MAP" or node.space != "TANGENT":
            self.warn_node(node, "normal")
            return None
        texture = self.texture(node.inputs["Color"], "normal map")
        if texture is not None:
            texture["scale"] = float(self.value(node.inputs["Strength"], "normal strength"))
        return texture

    def volume(self, output, entry):
        node, _ = linked_from(output.inputs["Volume"])
        if node is None:
            return
        if node.type != "VOLUME_ABSORPTION":
            self.export.warn("volume", "volumes other than Volume Absorption are not carried over")
            return
        # Cycles: sigma_a = density * (1 - colour) per metre; glTF: colour left after a distance.
        density = float(self.value(node.inputs["Density"], "volume density"))
        color = [float(c) for c in self.value(node.inputs["Color"], "volume colour")[:3]]
        entry.setdefault("extensions", {})["KHR_materials_volume"] = {
            "thicknessFactor": 1.0, "attenuationDistance": 1.0,
            "attenuationColor": [math.exp(-density * (1.0 - c)) for c in color]}
        self.use_extension("KHR_materials_volume")

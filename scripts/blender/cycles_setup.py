"""Cycles set up the way the project's references are rendered, for Blender's Python (bpy).

Imported by the scripts that render Cycles references and by `make bench` (its Cycles timings):
  lambert_materials()   every material tagged with the custom property "lambert" gets Cycles'
                        Diffuse BSDF instead of its Principled BSDF: exactly Lambertian, which is
                        the glTF BRDF with specular 0 (Principled v1 in Blender 3.x is Burley
                        diffuse with an extra specular layer, a few percent brighter)
  unbiased_cycles(...)  the integrator settings: no clamping, no denoising, no light threshold,
                        64 bounces of every kind, caustics on, box pixel filter 1 px, Standard view,
                        32-bit EXR output
"""
import bpy


def lambert_materials():
    for material in bpy.data.materials:
        if not material.get("lambert") or not material.use_nodes:
            continue
        tree = material.node_tree
        principled = next((n for n in tree.nodes if n.type == 'BSDF_PRINCIPLED'), None)
        output = next((n for n in tree.nodes if n.type == 'OUTPUT_MATERIAL'), None)
        if principled is None or output is None:
            continue
        diffuse = tree.nodes.new("ShaderNodeBsdfDiffuse")
        diffuse.inputs["Roughness"].default_value = 0.0
        color = principled.inputs["Base Color"]
        if color.is_linked:
            tree.links.new(color.links[0].from_socket, diffuse.inputs["Color"])
        else:
            diffuse.inputs["Color"].default_value = color.default_value
        normal = principled.inputs["Normal"]
        if normal.is_linked:  # a Normal Map node: the diffuse surface keeps it
            tree.links.new(normal.links[0].from_socket, diffuse.inputs["Normal"])
        surface = diffuse.outputs[0]
        strength = principled.inputs["Emission Strength"].default_value
        if strength > 0.0:
            emission = tree.nodes.new("ShaderNodeEmission")
            emission.inputs["Color"].default_value = principled.inputs["Emission"].default_value
            emission.inputs["Strength"].default_value = strength
            both = tree.nodes.new("ShaderNodeAddShader")
            tree.links.new(diffuse.outputs[0], both.inputs[0])
            tree.links.new(emission.outputs[0], both.inputs[1])
            surface = both.outputs[0]
        tree.links.new(surface, output.inputs["Surface"])


def unbiased_cycles(scene, samples, seed=0, time_limit=0.0):
    scene.render.engine = 'CYCLES'
    cycles = scene.cycles
    cycles.device = 'CPU'
    cycles.samples = samples
    cycles.time_limit = time_limit
    cycles.use_adaptive_sampling = False
    cycles.use_denoising = False
    cycles.seed = seed
    for bounces in ("max_bounces", "diffuse_bounces", "glossy_bounces", "transmission_bounces",
                    "transparent_max_bounces", "volume_bounces"):
        setattr(cycles, bounces, 64)
    cycles.min_light_bounces = 0
    cycles.sample_clamp_direct = 0.0
    cycles.sample_clamp_indirect = 0.0
    cycles.blur_glossy = 0.0
    cycles.caustics_reflective = True
    cycles.caustics_refractive = True
    cycles.light_sampling_threshold = 0.0
    cycles.pixel_filter_type = 'BOX'
    cycles.filter_width = 1.0
    scene.render.threads_mode = 'AUTO'
    scene.view_settings.view_transform = 'Standard'
    scene.view_settings.look = 'None'
    scene.view_settings.exposure = 0.0
    scene.view_settings.gamma = 1.0
    settings = scene.render.image_settings
    settings.file_format = 'OPEN_EXR'
    settings.color_depth = '32'
    settings.exr_codec = 'ZIP'

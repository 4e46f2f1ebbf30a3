# Which of Blender's render settings become which libveach render options.
#
# With "Use Cycles Settings" (the default) a .blend set up for Cycles renders with what it asks
# for: Cycles' samples, time limit, adaptive noise threshold, denoise, seed and animated seed,
# Light Paths' max bounces and Film's pixel filter. Otherwise the Veach panel's own settings apply.
# Either way the resolution, percentage, render region (border, crop) and Film > Transparent
# are Blender's own.
FILTERS = {"BOX": "box", "GAUSSIAN": "gaussian", "BLACKMAN_HARRIS": "blackman-harris"}


def frame_seed(seed, frame):
    """A different seed per frame from the scene's seed (a 32-bit integer hash of both)."""
    h = (seed * 0x9E3779B1 + frame * 0x85EBCA77) & 0xFFFFFFFF
    h ^= h >> 15
    h = (h * 0x2C1B3C6D) & 0xFFFFFFFF
    h ^= h >> 12
    return h & 0x7FFFFFFF


def uses_cycles(scene):
    return scene.veach.use_cycles_settings and getattr(scene, "cycles", None) is not None


def render_options(scene):
    """The libveach render options (name -> value) for the scene at its current frame."""
    own = scene.veach
    if uses_cycles(scene):
        cycles = scene.cycles
        options = {
            "spp": cycles.samples,
            "time_limit": float(cycles.time_limit),
            "noise": float(cycles.adaptive_threshold) if cycles.use_adaptive_sampling else 0.0,
            "max_depth": cycles.max_bounces,
            "filter": FILTERS.get(cycles.pixel_filter_type, "blackman-harris"),
            "filter_width": float(cycles.filter_width),
        }
        seed, animated = cycles.seed, cycles.use_animated_seed
    else:
        options = {
            "spp": own.samples,
            "time_limit": float(own.time_limit),
            "noise": float(own.noise_threshold),
            "max_depth": own.max_depth,
            "filter": own.filter_type,
            "filter_width": float(scene.render.filter_size),
        }
        seed, animated = own.seed, own.use_animated_seed
    options["denoise"] = 1 if denoising(scene) else 0
    options["seed"] = frame_seed(seed, scene.frame_current) if animated else seed
    options["integrator"] = own.integrator
    # Film > Transparent: the library leaves the background out of camera rays (it still lights
    # the scene) and puts the coverage in the Combined pass's alpha, premultiplied as Cycles'.
    options["transparent"] = 1 if scene.render.film_transparent else 0
    return options


def denoising(scene):
    """Render Properties > Sampling > Denoise: Cycles' own switch (scene.cycles.use_denoising, on in
    a new file as in Cycles) with Use Cycles Settings, else the Veach panel's (off by default)."""
    if uses_cycles(scene):
        return bool(scene.cycles.use_denoising)
    return bool(scene.veach.use_denoising)


def full_size(scene):
    """The image size: the resolution times its percentage."""
    scale = scene.render.resolution_percentage / 100.0
    return max(1, int(scene.render.resolution_x * scale)), max(1, int(scene.render.resolution_y * scale))


def region(scene):
    """The render region (x, y, width, height) in pixels of the full image, rows from the top
    (libveach's order), or None for the whole image. Blender keeps the border from the bottom
    left; its RenderResult for a border render is the region's size (padded back into the full
    frame by Blender itself unless Crop is on)."""
    r = scene.render
    if not r.use_border:
        return None
    width, height = full_size(scene)
    x0, x1 = int(r.border_min_x * width), int(r.border_max_x * width)
    y0, y1 = int(r.border_min_y * height), int(r.border_max_y * height)
    x1, y1 = max(x1, x0 + 1), max(y1, y0 + 1)
    if (x0, y0, x1, y1) == (0, 0, width, height):
        return None
    return x0, height - y1, x1 - x0, y1 - y0

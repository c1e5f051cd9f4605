"""Blender Cycles peer of `illum-bench converge` (bench/peers/README.md).

    blender -b --factory-startup --python-exit-code 1 --python cycles_peer.py -- --jobs JOBS.json
    blender -b --factory-startup --python-exit-code 1 --python cycles_peer.py -- --calibrate-ies

--jobs: builds the scene that `illum-bench converge` exported (SCENE.json + SCENE.bin, units
already Cycles': light powers in W, sun strength in W/m², emission strength = radiance),
renders one untimed warm-up sample (kernel loading), then each job {spp, seed, exr}, timed
from the start of path tracing (after the scene sync and BVH build) to the render's end,
saving 32-bit EXRs afterwards; writes {blender, settings, renders: [{exr, spp, seed,
seconds}]} to the jobs' `timings` file (through a temporary file).

--calibrate-ies: measures the scale Cycles applies to an IES profile on a point light (the
constant kCyclesIesScale in bench/suites/converge_stats.h): irradiance under a point light of
intensity 1 W/sr against the same light with a flat 1-candela profile.
"""
import json
import math
import os
import sys
import tempfile
import time
from array import array

import bpy
from mathutils import Matrix, Vector


def fail(message):
    print("cycles_peer: " + message, file=sys.stderr)
    sys.exit(1)


def configure(scene, data, threads):
    scene.render.engine = "CYCLES"
    scene.render.resolution_x = data["width"]
    scene.render.resolution_y = data["height"]
    scene.render.resolution_percentage = 100
    scene.render.pixel_aspect_x = scene.render.pixel_aspect_y = 1.0
    scene.render.film_transparent = False
    scene.render.use_compositing = False
    scene.render.use_sequencer = False
    if threads > 0:
        scene.render.threads_mode = "FIXED"
        scene.render.threads = threads
    c = scene.cycles
    c.device = "CPU"
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.use_preview_denoising = False
    bounces = data["cycles_max_bounces"]
    c.max_bounces = bounces
    c.diffuse_bounces = bounces
    c.glossy_bounces = bounces
    c.transmission_bounces = bounces
    c.volume_bounces = 0
    c.transparent_max_bounces = bounces
    # Unbiased settings: no clamping (the factory default clamps indirect light at 10), no
    # glossy blur; a 1-pixel box filter like illum's pixel.
    c.sample_clamp_direct = 0.0
    c.sample_clamp_indirect = 0.0
    c.blur_glossy = 0.0
    c.caustics_reflective = True
    c.caustics_refractive = True
    c.pixel_filter_type = "BOX"
    c.filter_width = 1.0
    c.use_animated_seed = False
    view = scene.view_settings
    view.view_transform = "Standard"
    view.look = "None"
    view.exposure = 0.0
    view.gamma = 1.0
    out = scene.render.image_settings
    out.file_format = "OPEN_EXR"
    out.color_mode = "RGB"
    out.color_depth = "32"
    out.exr_codec = "ZIP"
    world = bpy.data.worlds.new("background")
    world.use_nodes = True
    bg = world.node_tree.nodes["Background"]
    bg.inputs["Color"].default_value = (*data["background"], 1.0)
    bg.inputs["Strength"].default_value = 1.0
    scene.world = world


def look_at_matrix(position, forward, up):
    """Object matrix whose local -Z is `forward` and +Y is as close to `up` as allowed."""
    f = Vector(forward).normalized()
    right = f.cross(Vector(up))
    if right.length < 1e-6:
        right = f.cross(Vector((1.0, 0.0, 0.0)) if abs(f.x) < 0.9 else Vector((0.0, 1.0, 0.0)))
    right.normalize()
    true_up = right.cross(f)
    m = Matrix.Identity(4)
    for row in range(3):
        m[row][0], m[row][1], m[row][2], m[row][3] = right[row], true_up[row], -f[row], position[row]
    return m


def add_camera(scene, cam):
    data = bpy.data.cameras.new("camera")
    data.type = "PERSP"
    data.sensor_fit = "VERTICAL"
    data.angle_y = cam["fov_y"]
    data.clip_start = 1e-3
    data.clip_end = 1e5
    obj = bpy.data.objects.new("camera", data)
    scene.collection.objects.link(obj)
    p = Vector(cam["position"])
    obj.matrix_world = look_at_matrix(p, Vector(cam["look_at"]) - p, cam["up"])
    scene.camera = obj


def make_material(m):
    mat = bpy.data.materials.new(m["name"] or "material")
    mat.use_nodes = True
    nt = mat.node_tree
    nt.nodes.clear()
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    albedo = (*m["albedo"], 1.0)
    if m["type"] == "diffuse":
        bsdf = nt.nodes.new("ShaderNodeBsdfDiffuse")
        bsdf.inputs["Roughness"].default_value = 0.0  # Lambert, not Oren-Nayar
    elif m["type"] == "mirror":
        bsdf = nt.nodes.new("ShaderNodeBsdfGlossy")
        bsdf.distribution = "SHARP"
    else:
        fail("material %s: type %s is not mapped" % (m["name"], m["type"]))
    bsdf.inputs["Color"].default_value = albedo
    if m.get("albedo_texture"):
        tex = nt.nodes.new("ShaderNodeTexImage")
        tex.image = bpy.data.images.load(m["albedo_texture"], check_existing=True)
        tex.image.colorspace_settings.name = "sRGB" if m.get("albedo_texture_srgb", True) else "Non-Color"
        tex.interpolation = "Linear"
        tex.extension = "REPEAT"
        mix = nt.nodes.new("ShaderNodeMixRGB")
        mix.blend_type = "MULTIPLY"
        mix.inputs["Fac"].default_value = 1.0
        mix.inputs["Color1"].default_value = albedo
        nt.links.new(tex.outputs["Color"], mix.inputs["Color2"])
        nt.links.new(mix.outputs["Color"], bsdf.inputs["Color"])
    shader = bsdf.outputs[0]
    emission = m["emission"]
    peak = max(emission)
    if peak > 0.0:
        # Radiance = colour × strength; illum emits from the front face only, Cycles from
        # both: the strength is multiplied by (1 − backfacing).
        em = nt.nodes.new("ShaderNodeEmission")
        em.inputs["Color"].default_value = (*[e / peak for e in emission], 1.0)
        geo = nt.nodes.new("ShaderNodeNewGeometry")
        front = nt.nodes.new("ShaderNodeMath")
        front.operation = "SUBTRACT"
        front.inputs[0].default_value = 1.0
        nt.links.new(geo.outputs["Backfacing"], front.inputs[1])
        strength = nt.nodes.new("ShaderNodeMath")
        strength.operation = "MULTIPLY"
        strength.inputs[1].default_value = peak
        nt.links.new(front.outputs[0], strength.inputs[0])
        nt.links.new(strength.outputs[0], em.inputs["Strength"])
        add = nt.nodes.new("ShaderNodeAddShader")
        nt.links.new(shader, add.inputs[0])
        nt.links.new(em.outputs[0], add.inputs[1])
        shader = add.outputs[0]
    nt.links.new(shader, out.inputs["Surface"])
    return mat


def add_meshes(scene, data, folder):
    with open(os.path.join(folder, data["geometry"]), "rb") as f:
        blob = f.read()
    materials = [make_material(m) for m in data["materials"]]

    def floats(offset, count):
        a = array("f")
        a.frombytes(blob[offset:offset + 4 * count])
        return a, offset + 4 * count

    for i, m in enumerate(data["meshes"]):
        nv, nt_ = m["vertices"], m["triangles"]
        pos, o = floats(m["offset"], 3 * nv)
        nrm, o = floats(o, 3 * nv)
        uv = None
        if m["has_uv"]:
            uv, o = floats(o, 2 * nv)
        idx = array("I")
        idx.frombytes(blob[o:o + 4 * 3 * nt_])
        mesh = bpy.data.meshes.new("mesh%d" % i)
        mesh.vertices.add(nv)
        mesh.vertices.foreach_set("co", pos)
        mesh.loops.add(3 * nt_)
        mesh.loops.foreach_set("vertex_index", idx)
        mesh.polygons.add(nt_)
        mesh.polygons.foreach_set("loop_start", array("i", range(0, 3 * nt_, 3)))
        mesh.polygons.foreach_set("loop_total", array("i", [3]) * nt_)
        mesh.polygons.foreach_set("use_smooth", array("b", [1]) * nt_)
        if uv is not None:
            layer = mesh.uv_layers.new(name="UVMap")
            loop_uv = array("f", bytes(8 * 3 * nt_))
            for k, v in enumerate(idx):
                loop_uv[2 * k] = uv[2 * v]
                loop_uv[2 * k + 1] = uv[2 * v + 1]
            layer.data.foreach_set("uv", loop_uv)
        mesh.update()
        mesh.use_auto_smooth = True
        mesh.normals_split_custom_set_from_vertices(
            [(nrm[3 * v], nrm[3 * v + 1], nrm[3 * v + 2]) for v in range(nv)])
        mesh.materials.append(materials[m["material"]])
        obj = bpy.data.objects.new(m["name"] or "mesh%d" % i, mesh)
        # Cycles moves shadow-ray origins of smooth-shaded triangles towards the smooth
        # surface (geometry offset, default 0.1); illum offsets along the true normal only.
        obj.cycles.shadow_terminator_geometry_offset = 0.0
        obj.cycles.shadow_terminator_offset = 0.0
        scene.collection.objects.link(obj)


def write_flat_ies(path, half_angle_deg):
    """An IES profile of 1 candela inside the cone and 0 outside, every 0.1 degrees, so the
    ringing of Cycles' cubic interpolation at the edge is confined to 0.1 degrees."""
    edge = int(math.floor(half_angle_deg * 10.0))
    angles = [k / 10.0 for k in range(edge + 1)]
    values = [1.0] * len(angles)
    angles.append(half_angle_deg + 0.01)
    values.append(0.0)
    k = edge + 1
    while k <= 1800:
        if k / 10.0 > half_angle_deg + 0.01:
            angles.append(k / 10.0)
            values.append(0.0)
        k += 1
    with open(path, "w") as f:
        f.write("IESNA:LM-63-2002\nTILT=NONE\n")
        f.write("1 -1 1 %d 1 1 2 0 0 0\n1 1 0\n" % len(angles))
        f.write(" ".join("%.4f" % a for a in angles) + "\n0\n")
        f.write(" ".join("%g" % v for v in values) + "\n")


def add_lights(scene, data, folder):
    for i, l in enumerate(data["lights"]):
        kind = l["type"]
        if kind in ("point", "ies_spot"):
            light = bpy.data.lights.new(l["name"] or "light%d" % i, "POINT")
            light.shadow_soft_size = 0.0
            power = l["power_w"]
        elif kind == "sun":
            light = bpy.data.lights.new(l["name"] or "light%d" % i, "SUN")
            light.angle = 0.0
            power = l["strength"]
        else:
            fail("light %s: type %s is not mapped" % (l["name"], kind))
        peak = max(power)
        light.energy = peak
        light.color = [p / peak for p in power] if peak > 0 else (0.0, 0.0, 0.0)
        if kind == "ies_spot":
            ies_path = os.path.join(folder, "spot-%d.ies" % i)
            write_flat_ies(ies_path, math.degrees(l["cone_half_angle"]))
            light.use_nodes = True
            nt = light.node_tree
            ies = nt.nodes.new("ShaderNodeTexIES")
            ies.mode = "EXTERNAL"
            ies.filepath = ies_path
            nt.links.new(ies.outputs["Fac"], nt.nodes["Emission"].inputs["Strength"])
        obj = bpy.data.objects.new(light.name, light)
        scene.collection.objects.link(obj)
        obj.matrix_world = look_at_matrix(Vector(l["position"]), Vector(l["direction"]), (0.0, 1.0, 0.0))


_stats_times = []


def _on_stats(*_):
    # Blender 3.4 passes no text to render_stats handlers; the k-th call follows the k-th
    # status line it prints ("Fra:1 ... | Sample 0/N"), read back from the log afterwards.
    _stats_times.append((time.perf_counter(), time.process_time()))


class StatusLog:
    """Blender's status lines, from the file stdout goes to (the bench's log)."""

    def __init__(self):
        target = os.readlink("/proc/self/fd/1")
        if not os.path.isfile(target):
            fail("stdout must go to a file (the status lines time the path tracing)")
        self.path = target
        self.offset = os.path.getsize(target)

    def new_status_lines(self):
        sys.stdout.flush()
        with open(self.path, "rb") as f:
            f.seek(self.offset)
            text = f.read().decode("utf-8", "replace")
            self.offset = f.tell()
        return ["Fra:" + part for part in text.split("Fra:")[1:]]


def render(scene, spp, seed, log):
    """Renders and returns the seconds (wall, and process CPU time of all threads) from the start of path tracing (the first "Sample 0/"
    status, after the scene sync and BVH build) to the end of the render call. Persistent
    data cannot keep the scene between renders here (Blender 3.4 ignores a changed sample
    count with it), so each render syncs the scene and builds the BVH again; that part is
    left out of the time, as illum's BVH build is."""
    scene.cycles.samples = spp
    scene.cycles.seed = seed
    if log is None:  # untimed (calibration)
        bpy.ops.render.render(write_still=False)
        return 0.0, 0.0
    _stats_times.clear()
    if _on_stats not in bpy.app.handlers.render_stats:
        bpy.app.handlers.render_stats.append(_on_stats)
    log.new_status_lines()
    bpy.ops.render.render(write_still=False)
    end, end_cpu = time.perf_counter(), time.process_time()
    lines = log.new_status_lines()
    if len(lines) != len(_stats_times):
        fail("%d status lines but %d status calls: cannot time the path tracing" % (
            len(lines), len(_stats_times)))
    for line, (t, t_cpu) in zip(lines, _stats_times):
        if "| Sample 0/" in line:
            return end - t, end_cpu - t_cpu
    fail("no 'Sample 0/' status: cannot tell where path tracing started")


def run_jobs(jobs_path):
    with open(jobs_path) as f:
        jobs = json.load(f)
    with open(jobs["scene"]) as f:
        data = json.load(f)
    if data.get("format") != "illum-peer-scene 1":
        fail("%s: not an illum peer scene" % jobs["scene"])
    folder = os.path.dirname(os.path.abspath(jobs["scene"]))
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    configure(scene, data, int(jobs.get("threads", 0)))
    add_camera(scene, data["camera"])
    add_meshes(scene, data, folder)
    add_lights(scene, data, folder)
    log = StatusLog()
    render(scene, 1, 0, log)  # warm-up: kernel loading, image decoding
    results = []
    for job in jobs["renders"]:
        seconds, cpu_seconds = render(scene, int(job["spp"]), int(job["seed"]), log)
        bpy.data.images["Render Result"].save_render(job["exr"], scene=scene)
        results.append({"exr": job["exr"], "spp": job["spp"], "seed": job["seed"], "seconds": seconds,
                        "cpu_seconds": cpu_seconds})
        print("cycles_peer: %s %d spp in %.3f s" % (os.path.basename(job["exr"]), job["spp"], seconds))
    c = scene.cycles
    settings = {k: getattr(c, k) for k in (
        "max_bounces", "diffuse_bounces", "glossy_bounces", "sample_clamp_direct",
        "sample_clamp_indirect", "sampling_pattern", "pixel_filter_type", "filter_width",
        "light_sampling_threshold", "min_light_bounces", "use_adaptive_sampling", "use_denoising")}
    settings["threads"] = scene.render.threads
    out = {"blender": bpy.app.version_string, "settings": settings, "renders": results}
    fd, tmp = tempfile.mkstemp(dir=os.path.dirname(jobs["timings"]))
    with os.fdopen(fd, "w") as f:
        json.dump(out, f, indent=2)
    os.replace(tmp, jobs["timings"])


def calibrate_ies():
    """Irradiance at the nadir 1 m under a point light of 1 W/sr, without and with a flat
    1-candela IES profile (a diffuse plane of albedo 1 seen by an orthographic camera: the
    pixel value is E/π)."""
    values = {}
    folder = tempfile.mkdtemp()
    for mode in ("point", "ies"):
        bpy.ops.wm.read_factory_settings(use_empty=True)
        scene = bpy.context.scene
        data = {"width": 4, "height": 4, "cycles_max_bounces": 0, "background": [0, 0, 0]}
        configure(scene, data, 0)
        mesh = bpy.data.meshes.new("plane")
        mesh.from_pydata([(-50, -50, 0), (50, -50, 0), (50, 50, 0), (-50, 50, 0)], [], [(0, 1, 2, 3)])
        mesh.materials.append(make_material({"name": "white", "type": "diffuse", "albedo": [1, 1, 1],
                                             "emission": [0, 0, 0]}))
        obj = bpy.data.objects.new("plane", mesh)
        scene.collection.objects.link(obj)
        cam = bpy.data.cameras.new("camera")
        cam.type = "ORTHO"
        cam.ortho_scale = 0.01
        co = bpy.data.objects.new("camera", cam)
        co.location = (0, 0, 0.5)
        scene.collection.objects.link(co)
        scene.camera = co
        light = {"name": "l", "type": "point" if mode == "point" else "ies_spot",
                 "position": [0, 0, 1], "direction": [0, 0, -1], "cone_half_angle": math.radians(40),
                 "power_w": [4 * math.pi] * 3}
        add_lights(scene, {"lights": [light]}, folder)
        render(scene, 16, 0, None)
        path = os.path.join(folder, mode + ".exr")
        bpy.data.images["Render Result"].save_render(path, scene=scene)
        img = bpy.data.images.load(path)
        px = list(img.pixels)
        values[mode] = sum(px[0::4]) / (len(px) // 4)
    print("cycles_peer: point E/pi %.6f, flat IES E/pi %.6f, IES scale %.6f (Blender %s)" % (
        values["point"], values["ies"], values["ies"] / values["point"], bpy.app.version_string))


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    if argv[:1] == ["--calibrate-ies"]:
        calibrate_ies()
    elif len(argv) == 2 and argv[0] == "--jobs":
        run_jobs(argv[1])
    else:
        fail("usage: blender -b --python cycles_peer.py -- --jobs JOBS.json | --calibrate-ies")


try:
    main()
except SystemExit:
    raise
except Exception as e:  # Blender would print the traceback and still exit 0
    import traceback
    traceback.print_exc()
    fail(str(e))

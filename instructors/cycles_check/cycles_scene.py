"""Builds scene_json's scene in Blender's Cycles and renders it to a PFM.

Run by Blender, not by Python:

  blender -b --factory-startup -noaudio --python cycles_scene.py -- \
      SCENE.json OUT.pfm --samples N --max-depth M [--seed S] [--threads T]

The scene is this project's (read by its own loader: scene_json), so the
two renders differ only where the renderers do. What is built, and how each
of this project's conventions is met in Cycles (README.md explains why):

  camera       a perspective camera with the world matrix of the camera's
               axes, the horizontal field of view, square pixels; a box
               pixel filter one pixel wide (ours: uniform samples in the
               pixel); the thin lens from lens_radius and focal_distance
  triangles    one mesh per material, with the loader's vertex normals as
               custom normals
  spheres      fine icospheres with the sphere's normals (add_sphere)
  diffuse      Diffuse BSDF (Lambert) on the side its normal faces;
               seen from behind, Translucent (ours shades with the normal as
               it is, so a diffuse surface hit from behind gathers and
               sends its light on the normal's side)
  mirror       Glossy BSDF, sharp, colour = reflectance
  glass        a mix of sharp Refraction and sharp Glossy by Schlick's
               reflectance at the angle on the air's side, 1 past the
               critical angle (ours, stages/part6_mirror_glass); the
               radiance scaling by eta^2 that ours applies cancels over a
               closed object's entry and exit
  refraction   sharp Refraction BSDF
  microfacet   Glossy BSDF, Beckmann, roughness sqrt(alpha) (Cycles' alpha
               is roughness squared), colour = the conductor's Fresnel
               reflectance per channel at the angle of the outgoing
               direction (ours takes the incoming one: Cycles fixes a
               closure's colour before it picks the light)
  area light   a Cycles area light of the same rectangle and radiance,
               reached by light sampling only (ours never hits a light
               with a ray) and invisible to the camera
  emitting     its emission counts for camera rays and after mirror and
  mesh         glass bounces only, as ours counts it (a course scene's
               visible light rectangle need not be where its area light is)
  environment  the world: the map, nearest texel, through the same
               latitude-longitude convention (common/environment.h), plus
               the ambient lights' radiance where d.y > 0
  -m M         Cycles' bounce limit M - 1 (it counts direct light at the
               first hit as bounce 0); no clamping, no glossy filter,
               caustics on
Anything else (point and directional lights; an emitting sphere; a
material that both reflects and emits) stops the script with a message:
there is no faithful translation to compare against.
"""
import json
import math
import os
import sys

import bpy
import numpy as np


def fail(msg):
    print("cycles_scene.py: " + msg, file=sys.stderr)
    sys.exit(1)


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    if len(argv) < 2:
        fail("usage: blender -b --python cycles_scene.py -- SCENE.json OUT.pfm --samples N --max-depth M "
             "[--seed S] [--threads T]")
    opts = {"scene": argv[0], "out": argv[1], "samples": 64, "max_depth": 5, "seed": 0, "threads": 1}
    numeric = ("samples", "max_depth", "seed", "threads")
    i = 2
    while i < len(argv):
        key = argv[i].lstrip("-").replace("-", "_")
        if key not in numeric or i + 1 >= len(argv):
            fail("unknown or incomplete option " + argv[i])
        try:
            opts[key] = int(argv[i + 1])
        except ValueError:
            fail("%s needs a whole number, not '%s'" % (argv[i], argv[i + 1]))
        i += 2
    return opts


# --- shader node helpers ---------------------------------------------------

class Graph:
    """Shorthand for building a material's node tree."""

    def __init__(self, tree):
        self.tree = tree
        self.nodes = tree.nodes
        self.links = tree.links

    def node(self, kind, **props):
        n = self.nodes.new(kind)
        for k, v in props.items():
            setattr(n, k, v)
        return n

    def link(self, out, inp):
        self.links.new(out, inp)

    def math(self, op, a, b=None):
        n = self.node("ShaderNodeMath", operation=op)
        for sock, v in ((n.inputs[0], a), (n.inputs[1], b)):
            if v is None:
                continue
            if isinstance(v, (int, float)):
                sock.default_value = float(v)
            else:
                self.link(v, sock)
        return n.outputs[0]


def new_material(name):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    g = Graph(mat.node_tree)
    g.nodes.clear()
    out = g.node("ShaderNodeOutputMaterial")
    return mat, g, out


def rgba(c):
    return (float(c[0]), float(c[1]), float(c[2]), 1.0)


def schlick(g, cos, ior):
    r = ((1.0 - ior) / (1.0 + ior)) ** 2
    one_minus = g.math("SUBTRACT", 1.0, cos)
    return g.math("ADD", r, g.math("MULTIPLY", 1.0 - r, g.math("POWER", one_minus, 5.0)))


def glass_choice(g, ior):
    """Schlick's reflectance at the angle on the air's side; 1 past TIR."""
    geo = g.node("ShaderNodeNewGeometry")
    dot = g.node("ShaderNodeVectorMath", operation="DOT_PRODUCT")
    g.link(geo.outputs["Normal"], dot.inputs[0])
    g.link(geo.outputs["Incoming"], dot.inputs[1])
    c = g.math("ABSOLUTE", dot.outputs["Value"])
    inside = geo.outputs["Backfacing"]
    # Inside the glass: sin^2 of the way out, eta = ior.
    s2 = g.math("MULTIPLY", ior * ior, g.math("SUBTRACT", 1.0, g.math("MULTIPLY", c, c)))
    cos_out = g.math("SQRT", g.math("MAXIMUM", g.math("SUBTRACT", 1.0, s2), 0.0))
    cos_air = g.math("ADD", g.math("MULTIPLY", c, g.math("SUBTRACT", 1.0, inside)), g.math("MULTIPLY", cos_out, inside))
    tir = g.math("MULTIPLY", inside, g.math("GREATER_THAN", s2, 1.0))
    return g.math("MAXIMUM", schlick(g, cos_air, ior), tir)


def conductor_fresnel(g, eta, k):
    """Ours (stages/part7_microfacet): per channel (A C - B^2) / ((A + B)(C + B)),
    A = eta^2 + k^2 + cos^2, B = 2 eta cos, C = (eta^2 + k^2) cos^2 + 1, at the
    outgoing direction's cos."""
    geo = g.node("ShaderNodeNewGeometry")
    dot = g.node("ShaderNodeVectorMath", operation="DOT_PRODUCT")
    g.link(geo.outputs["Normal"], dot.inputs[0])
    g.link(geo.outputs["Incoming"], dot.inputs[1])
    c = g.math("MINIMUM", g.math("MAXIMUM", dot.outputs["Value"], 0.0), 1.0)
    c2 = g.math("MULTIPLY", c, c)
    comb = g.node("ShaderNodeCombineColor")
    for i in range(3):
        a = float(eta[i]) ** 2 + float(k[i]) ** 2
        A = g.math("ADD", c2, a)
        B = g.math("MULTIPLY", c, 2.0 * float(eta[i]))
        C = g.math("ADD", g.math("MULTIPLY", c2, a), 1.0)
        num = g.math("SUBTRACT", g.math("MULTIPLY", A, C), g.math("MULTIPLY", B, B))
        den = g.math("MULTIPLY", g.math("ADD", A, B), g.math("ADD", C, B))
        g.link(g.math("DIVIDE", num, den), comb.inputs[i])
    return comb.outputs[0]


def build_material(m):
    mat, g, out = new_material(m["name"] or "material")
    t = m["type"]
    if t == "diffuse":
        # Ours builds the shading frame on the normal as it is (the
        # course's), so a diffuse surface hit from behind its normal gathers
        # the light on the normal's side and sends its bounce there: a
        # diffuse transmission (Cycles' Translucent) seen from that side.
        # add_mesh winds each triangle to its normals' side, so Cycles'
        # Backfacing is "behind our normal".
        front = g.node("ShaderNodeBsdfDiffuse")
        front.inputs["Color"].default_value = rgba(m["albedo"])
        front.inputs["Roughness"].default_value = 0.0
        back = g.node("ShaderNodeBsdfTranslucent")
        back.inputs["Color"].default_value = rgba(m["albedo"])
        mix = g.node("ShaderNodeMixShader")
        g.link(g.node("ShaderNodeNewGeometry").outputs["Backfacing"], mix.inputs["Fac"])
        g.link(front.outputs[0], mix.inputs[1])
        g.link(back.outputs[0], mix.inputs[2])
        g.link(mix.outputs[0], out.inputs["Surface"])
    elif t == "mirror":
        bsdf = g.node("ShaderNodeBsdfGlossy", distribution="SHARP")
        bsdf.inputs["Color"].default_value = rgba(m["reflectance"])
        g.link(bsdf.outputs[0], out.inputs["Surface"])
    elif t in ("glass", "refraction"):
        refr = g.node("ShaderNodeBsdfRefraction", distribution="SHARP")
        refr.inputs["Color"].default_value = rgba(m["transmittance"])
        refr.inputs["IOR"].default_value = float(m["ior"])
        if t == "refraction":
            g.link(refr.outputs[0], out.inputs["Surface"])
        else:
            refl = g.node("ShaderNodeBsdfGlossy", distribution="SHARP")
            refl.inputs["Color"].default_value = rgba(m["reflectance"])
            mix = g.node("ShaderNodeMixShader")
            g.link(glass_choice(g, float(m["ior"])), mix.inputs["Fac"])
            g.link(refr.outputs[0], mix.inputs[1])
            g.link(refl.outputs[0], mix.inputs[2])
            g.link(mix.outputs[0], out.inputs["Surface"])
    elif t == "microfacet":
        bsdf = g.node("ShaderNodeBsdfGlossy", distribution="BECKMANN")
        bsdf.inputs["Roughness"].default_value = math.sqrt(float(m["alpha"]))
        g.link(conductor_fresnel(g, m["eta"], m["k"]), bsdf.inputs["Color"])
        g.link(bsdf.outputs[0], out.inputs["Surface"])
    else:
        fail("material '%s': unknown type %s" % (m["name"], t))
    return mat


def seen_emission_material(m):
    """An emitting mesh as ours treats it: its emission (both sides) counts
    for camera rays and after a mirror or glass bounce (a singular ray in
    Cycles), the last vertex's too (stages/part4_global_illumination), never
    otherwise (no light is sampled on it, and a diffuse or microfacet bounce
    that hits it finds black: its light comes from the scene's area lights
    instead)."""
    mat, g, out = new_material(m["name"] or "emission")
    em = g.node("ShaderNodeEmission")
    em.inputs["Color"].default_value = rgba(m["emission"])
    em.inputs["Strength"].default_value = 1.0
    path = g.node("ShaderNodeLightPath")
    seen = g.math("MAXIMUM", path.outputs["Is Camera Ray"], path.outputs["Is Singular Ray"])
    black = g.node("ShaderNodeBsdfDiffuse")
    black.inputs["Color"].default_value = (0, 0, 0, 1)
    mix = g.node("ShaderNodeMixShader")
    g.link(seen, mix.inputs["Fac"])
    g.link(black.outputs[0], mix.inputs[1])
    g.link(em.outputs[0], mix.inputs[2])
    g.link(mix.outputs[0], out.inputs["Surface"])
    mat.cycles.sample_as_light = False
    return mat


def add_area_light(name, l):
    """Ours: a one-sided parallelogram of radiance L, sampled by points on it
    and never hit by a ray. Cycles: a rectangular area light, reached only
    by light sampling (no multiple importance sampling, so no ray hits it)
    and seen by no camera ray. Cycles' power P gives radiance P / (4 A)
    (measured: P = pi L A gave pi / 4 of ours everywhere)."""
    from mathutils import Matrix
    dx, dy = np.asarray(l["dim_x"], float), np.asarray(l["dim_y"], float)
    d = np.asarray(l["direction"], float)
    sx, sy = np.linalg.norm(dx), np.linalg.norm(dy)
    if abs(np.dot(dx, dy)) > 1e-6 * sx * sy:
        fail("area light %s is not a rectangle" % name)
    ex, ey = dx / sx, dy / sy
    ez = -d  # Cycles' area light emits along its local -Z
    if np.dot(np.cross(ex, ey), ez) < 0:
        ey = -ey
    light = bpy.data.lights.new(name, "AREA")
    light.shape = "RECTANGLE"
    light.size, light.size_y = sx, sy
    rad = np.asarray(l["radiance"], float)
    peak = float(rad.max())
    if peak <= 0:
        return
    light.color = tuple(rad / peak)
    light.energy = 4.0 * peak * sx * sy
    light.cycles.use_multiple_importance_sampling = False
    light.cycles.cast_shadow = True
    obj = bpy.data.objects.new(name, light)
    # 1e-4 forward: Cycles' shadow ray to a point on the light reaches it,
    # and would stop on an emitting mesh in the light's plane (ours stops
    # its shadow rays short of the light).
    p = np.asarray(l["position"], float) + 1e-4 * d
    obj.matrix_world = Matrix(((ex[0], ey[0], ez[0], p[0]), (ex[1], ey[1], ez[1], p[1]),
                               (ex[2], ey[2], ez[2], p[2]), (0, 0, 0, 1)))
    obj.visible_camera = False
    bpy.context.scene.collection.objects.link(obj)


# --- geometry --------------------------------------------------------------

def add_mesh(name, tris, normals, mat):
    """tris: (n, 3, 3) positions; normals: (n, 3, 3) vertex normals."""
    n = len(tris)
    # Wind each triangle so that its geometric normal is on its vertex
    # normals' side: Cycles flips the shading normal of a triangle seen from
    # behind its winding; ours shades with the vertex normals as they are.
    geo = np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0])
    flip = np.einsum("ij,ij->i", geo, normals.sum(axis=1)) < 0
    tris, normals = tris.copy(), normals.copy()
    tris[flip] = tris[flip][:, ::-1]
    normals[flip] = normals[flip][:, ::-1]
    verts = tris.reshape(-1, 3)
    faces = np.arange(3 * n, dtype=np.int32).reshape(n, 3)
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(verts.tolist(), [], faces.tolist())
    mesh.update()
    # Polygons keep the order given, loops follow their vertices.
    mesh.use_auto_smooth = True
    mesh.normals_split_custom_set(normals.reshape(-1, 3).tolist())
    mesh.materials.append(mat)
    obj = bpy.data.objects.new(name, mesh)
    # Cycles moves shadow rays off smooth low-poly surfaces by default; ours
    # starts them on the surface.
    obj.cycles.shadow_terminator_geometry_offset = 0.0
    obj.cycles.shadow_terminator_offset = 0.0
    bpy.context.scene.collection.objects.link(obj)
    return obj


def add_sphere(name, center, radius, mat):
    """An icosphere of 7 subdivisions (327,680 triangles; its faces lie
    within 3e-5 radii of the sphere) with the sphere's exact normals at its
    vertices. (Cycles' point primitive is a true sphere, but a ray that
    starts inside one does not hit it on the way out: no refraction.)"""
    import bmesh
    bm = bmesh.new()
    bmesh.ops.create_icosphere(bm, subdivisions=7, radius=float(radius))
    mesh = bpy.data.meshes.new(name)
    bm.to_mesh(mesh)
    bm.free()
    co = np.empty(3 * len(mesh.vertices), np.float32)
    mesh.vertices.foreach_get("co", co)
    co = co.reshape(-1, 3)
    normals = co / np.linalg.norm(co, axis=1, keepdims=True)
    mesh.use_auto_smooth = True
    mesh.normals_split_custom_set_from_vertices(normals.tolist())
    mesh.materials.append(mat)
    obj = bpy.data.objects.new(name, mesh)
    obj.location = [float(c) for c in center]
    obj.cycles.shadow_terminator_geometry_offset = 0.0
    obj.cycles.shadow_terminator_offset = 0.0
    bpy.context.scene.collection.objects.link(obj)
    return obj


# --- scene -----------------------------------------------------------------

def setup_camera(cam_json, width, height):
    cam = bpy.data.cameras.new("camera")
    cam.type = "PERSP"
    cam.sensor_fit = "HORIZONTAL"
    cam.sensor_width = 36.0
    cam.angle_x = math.radians(cam_json["hfov_deg"])
    cam.clip_start = cam_json["near_clip"]
    cam.clip_end = cam_json["far_clip"]
    if cam_json["lens_radius"] > 0:
        cam.dof.use_dof = True
        cam.dof.focus_distance = cam_json["focal_distance"]
        # Cycles' aperture radius is lens / (2 f-stop) in metres of a
        # millimetre lens: one scene unit = one metre.
        cam.dof.aperture_fstop = cam.lens * 1e-3 / (2.0 * cam_json["lens_radius"])
        cam.dof.aperture_blades = 0
    obj = bpy.data.objects.new("camera", cam)
    from mathutils import Matrix
    ax, ay, az, pos = (cam_json[k] for k in ("axis_x", "axis_y", "axis_z", "position"))
    obj.matrix_world = Matrix(((ax[0], ay[0], az[0], pos[0]), (ax[1], ay[1], az[1], pos[1]),
                               (ax[2], ay[2], az[2], pos[2]), (0, 0, 0, 1)))
    bpy.context.scene.collection.objects.link(obj)
    bpy.context.scene.camera = obj
    # The vertical field of view follows from square pixels; check ours does.
    tan_v = math.tan(math.radians(cam_json["hfov_deg"]) / 2) * height / width
    if abs(tan_v / math.tan(math.radians(cam_json["vfov_deg"]) / 2) - 1) > 1e-4:
        fail("the camera's pixels are not square (hfov %g, vfov %g at %dx%d)" %
             (cam_json["hfov_deg"], cam_json["vfov_deg"], width, height))


def setup_world(env_path, ambient):
    """The light from infinity: the environment map (-e) plus the ambient
    lights' radiance over the upper hemisphere (d.y > 0), as ours adds them
    (common/lights.h, escaped_radiance)."""
    world = bpy.data.worlds.new("world")
    bpy.context.scene.world = world
    world.use_nodes = True
    g = Graph(world.node_tree)
    g.nodes.clear()
    out = g.node("ShaderNodeOutputWorld")
    bg = g.node("ShaderNodeBackground")
    g.link(bg.outputs[0], out.inputs["Surface"])
    bg.inputs["Strength"].default_value = 1.0
    if env_path is None and not any(ambient):
        bg.inputs["Color"].default_value = (0, 0, 0, 1)
        bg.inputs["Strength"].default_value = 0.0
        return
    coord = g.node("ShaderNodeTexCoord")
    sep = g.node("ShaderNodeSeparateXYZ")
    g.link(coord.outputs["Generated"], sep.inputs[0])
    colour = None
    if env_path is not None:
        img = bpy.data.images.load(os.path.abspath(env_path))
        img.colorspace_settings.name = "Non-Color"
        tex = g.node("ShaderNodeTexEnvironment", interpolation="Closest", projection="EQUIRECTANGULAR")
        tex.image = img
        # Ours: theta = acos(d.y), phi = atan2(-d.z, d.x) + pi, u = phi / 2 pi
        # from the left, theta / pi from the top. Cycles' map of a direction D:
        # u = 1/2 - atan2(D.y, D.x) / 2 pi, v = 1 - acos(D.z) / pi from the
        # bottom. They agree for D = (d.x, d.z, d.y).
        comb = g.node("ShaderNodeCombineXYZ")
        g.link(sep.outputs["X"], comb.inputs["X"])
        g.link(sep.outputs["Z"], comb.inputs["Y"])
        g.link(sep.outputs["Y"], comb.inputs["Z"])
        g.link(comb.outputs[0], tex.inputs["Vector"])
        colour = tex.outputs["Color"]
        world.cycles.sampling_method = "MANUAL"
        world.cycles.sample_map_resolution = max(img.size[0], img.size[1])
    if any(ambient):
        up = g.math("GREATER_THAN", sep.outputs["Y"], 0.0)
        amb = g.node("ShaderNodeMixRGB", blend_type="MULTIPLY")
        amb.inputs["Fac"].default_value = 1.0
        amb.inputs["Color1"].default_value = rgba(ambient)
        up_rgb = g.node("ShaderNodeCombineColor")
        for i in range(3):
            g.link(up, up_rgb.inputs[i])
        g.link(up_rgb.outputs[0], amb.inputs["Color2"])
        if colour is None:
            colour = amb.outputs[0]
        else:
            add = g.node("ShaderNodeMixRGB", blend_type="ADD")
            add.inputs["Fac"].default_value = 1.0
            g.link(colour, add.inputs["Color1"])
            g.link(amb.outputs[0], add.inputs["Color2"])
            colour = add.outputs[0]
        if env_path is None:
            world.cycles.sampling_method = "MANUAL"
            world.cycles.sample_map_resolution = 64
    g.link(colour, bg.inputs["Color"])


def setup_render(opts, width, height):
    sc = bpy.context.scene
    sc.render.engine = "CYCLES"
    cy = sc.cycles
    cy.device = "CPU"
    cy.samples = opts["samples"]
    cy.use_adaptive_sampling = False
    cy.use_denoising = False
    cy.seed = opts["seed"]
    bounces = max(opts["max_depth"] - 1, 0)
    cy.max_bounces = bounces
    cy.diffuse_bounces = cy.glossy_bounces = cy.transmission_bounces = bounces
    cy.volume_bounces = 0
    cy.transparent_max_bounces = 0
    cy.sample_clamp_direct = 0.0
    cy.sample_clamp_indirect = 0.0
    cy.blur_glossy = 0.0
    cy.caustics_reflective = True
    cy.caustics_refractive = True
    cy.light_sampling_threshold = 0.0
    cy.filter_type = "BOX"
    cy.filter_width = 1.0
    sc.render.threads_mode = "FIXED"
    sc.render.threads = opts["threads"]
    sc.render.resolution_x = width
    sc.render.resolution_y = height
    sc.render.resolution_percentage = 100
    sc.render.pixel_aspect_x = sc.render.pixel_aspect_y = 1.0
    sc.render.film_transparent = False
    sc.view_settings.view_transform = "Standard"
    sc.render.image_settings.file_format = "OPEN_EXR"
    sc.render.image_settings.color_depth = "32"
    sc.render.image_settings.color_mode = "RGB"


def write_pfm(path, rgb):
    """rgb: (height, width, 3) rows from the bottom, as PFM stores them."""
    h, w, _ = rgb.shape
    tmp = path + ".partial"
    with open(tmp, "wb") as f:
        f.write(b"PF\n%d %d\n-1.0\n" % (w, h))
        f.write(np.ascontiguousarray(rgb, dtype="<f4").tobytes())
    os.replace(tmp, path)


def main():
    opts = parse_args()
    with open(opts["scene"]) as f:
        scene = json.load(f)
    width, height = scene["width"], scene["height"]

    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj, do_unlink=True)

    setup_camera(scene["camera"], width, height)
    ambient = [sum(l["radiance"][i] for l in scene["lights"] if l["type"] == "ambient") for i in range(3)]
    setup_world(scene["environment_map"], ambient)
    setup_render(opts, width, height)

    lights = scene["lights"]
    for light in lights:
        if light["type"] not in ("area", "environment", "ambient"):
            fail("light type %s is not translated" % light["type"])
    area = [l for l in lights if l["type"] == "area"]
    if any(l["type"] == "environment" for l in lights) and scene["environment_map"] is None:
        fail("an environment light without a map")

    mats = scene["materials"]
    t = scene["triangles"]
    pos = np.asarray(t["positions"], float).reshape(-1, 3, 3)
    nrm = np.asarray(t["normals"], float).reshape(-1, 3, 3)
    tri_mat = np.asarray(t["materials"], int)
    built = {}

    def material(i):
        if i not in built:
            built[i] = build_material(mats[i])
        return built[i]

    for i in sorted(set(tri_mat.tolist())):
        sel = np.nonzero(tri_mat == i)[0]
        emits = mats[i]["type"] == "emission" or any(c > 0 for c in mats[i]["emission"])
        if emits and mats[i]["type"] != "emission":
            fail("material '%s' both reflects and emits: not translated" % mats[i]["name"])
        add_mesh("mesh-%d" % i, pos[sel], nrm[sel], seen_emission_material(mats[i]) if emits else material(i))

    for j, s in enumerate(scene["spheres"]):
        m = mats[s["material"]]
        if m["type"] == "emission" or any(c > 0 for c in m["emission"]):
            fail("sphere %d emits: not translated" % j)
        add_sphere("sphere-%d" % j, s["center"], s["radius"], material(s["material"]))

    for j, l in enumerate(area):
        add_area_light("light-%d" % j, l)

    exr = opts["out"] + ".exr"
    bpy.context.scene.render.filepath = exr
    bpy.ops.render.render(write_still=True)
    img = bpy.data.images.load(exr)
    px = np.array(img.pixels[:], dtype=np.float32).reshape(height, width, 4)[:, :, :3]
    write_pfm(opts["out"], px)
    os.remove(exr)
    print("cycles_scene.py: wrote %s (%dx%d, %d samples, max depth %d, seed %d)" %
          (opts["out"], width, height, opts["samples"], opts["max_depth"], opts["seed"]))


main()

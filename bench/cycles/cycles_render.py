# Renders a glTF 2.0 scene with Blender's Cycles the way Lancer's path tracer renders it, so
# that the two can be compared at equal error. An optional benchmark peer: neither the build
# nor the tests need Blender (Debian 12: apt-get install blender python3-numpy; 3.4.1).
#
#   blender -b --factory-startup -P bench/cycles/cycles_render.py -- --scene scenes/cornell-box.gltf \
#       --output /tmp/cycles.exr [--width 256 --height 256 --spp 256 --max-bounces 64 --threads 0
#       --seed 0 --camera 0]
#
# Writes a linear float RGBA OpenEXR (32-bit, ZIP) and prints one line, render_seconds being
# bpy.ops.render.render alone:  cycles_render: {"render_seconds": 28.71, "width": 256, ...}
# On failure it prints "cycles_render: error: ..." and exits with status 1.
#
# What differs from Blender's defaults, and why (Blender Python API names):
# - scene.cycles: use_adaptive_sampling, use_denoising False; sample_clamp_direct/_indirect,
#   blur_glossy, light_sampling_threshold 0; caustics_reflective/_refractive True; max_bounces
#   and diffuse/glossy/transmission/volume_bounces, transparent_max_bounces = --max-bounces:
#   no bias, as Lancer. Cycles' max_bounces N is Lancer's --max-depth N + 1 (checked at 0/1).
# - pixel_filter_type 'BOX', filter_width 1: Lancer jitters uniformly over the pixel.
# - A black world (Background strength 0, world.cycles.sampling_method 'NONE');
#   render.film_transparent False; view_settings 'Standard', look 'None', exposure 0, gamma 1.
# - Materials: the importer's Principled BSDF (Disney diffuse, specular added without 1 - F:
#   the Cornell box comes out 4-37 % brighter per region than in Lancer) becomes the BRDF of
#   Lancer's src/render/bsdf.h: a Lambert Diffuse BSDF weighted by Lancer's 1 - specular
#   F(V.H) (averaged over cosine-weighted light directions: a fit in N.V), plus a
#   specular-only Principled (base colour black: its GGX lobe with Fresnel), mixed by
#   transmission with a Principled glass and by metallic with a Principled metal (single-
#   scattering GGX, as Lancer). KHR_materials_volume thickness 0 is a thin wall
#   (Transparent/Glossy by Fresnel), else a refracting volume with Lancer's Beer-Lambert
#   sigma_a = -ln(attenuationColor) / attenuationDistance. Emission: emissiveFactor x
#   KHR_materials_emissive_strength as radiance (the Emission node's Strength x Color), from
#   the front side only, as Lancer. alphaMode is ignored, as Lancer.
# - Lights: convert_lighting_mode 'COMPAT' (glTF units read as W/sr and W/m^2, as Lancer),
#   shadow_soft_size 0 (delta lights). Blender's spot falloff is not glTF's (warned).
# - Camera: sensor_fit 'VERTICAL' so yfov spans the image height; Lancer's camera extras
#   "aperture" (lens radius) and "focusDistance" set dof.aperture_fstop and dof.focus_distance.
import argparse, json, math, os, sys, time

import numpy as np
for _name, _type in (("bool", bool), ("int", int), ("float", float), ("object", object), ("str", str)):
    if _name not in np.__dict__:
        setattr(np, _name, _type)  # numpy 1.24 dropped aliases that the 3.4 importer still uses
import bpy
from io_scene_gltf2.blender.imp.gltf2_blender_camera import BlenderCamera
from io_scene_gltf2.blender.imp.gltf2_blender_material import BlenderMaterial


def warn(msg):
    print("cycles_render: warning: " + msg, file=sys.stderr)


def fail(msg):
    print("cycles_render: error: " + msg, flush=True)
    sys.exit(1)


def tag(datablock, **properties):  # as custom properties
    for key, value in properties.items():
        datablock[key] = value
    return datablock


def tag_imported_data():
    """Wrap the importer's constructors to note which glTF camera / material each datablock is."""
    make_camera, make_material = BlenderCamera.create, BlenderMaterial.create

    def camera(gltf, vnode, index):
        cam = make_camera(gltf, vnode, index)
        yfov = getattr(gltf.data.cameras[index].perspective, "yfov", None) or 0.0
        return tag(cam, gltf_camera=index, order=len(bpy.data.cameras), yfov=yfov)

    def material(gltf, index, vertex_color):
        make_material(gltf, index, vertex_color)
        m = gltf.data.materials[index]
        ext = m.extensions or {}
        spec, vol = ext.get("KHR_materials_specular", {}), ext.get("KHR_materials_volume", {})
        strength = ext.get("KHR_materials_emissive_strength", {}).get("emissiveStrength", 1.0)
        distance = vol.get("attenuationDistance", math.inf)
        tag(bpy.data.materials[m.blender_material[vertex_color]],
            emission=[e * strength for e in (m.emissive_factor or [0.0] * 3)],
            ior=ext.get("KHR_materials_ior", {}).get("ior", 1.5), specular=spec.get("specularFactor", 1.0),
            specular_color=max(spec.get("specularColorFactor", [1.0])), thin=not vol.get("thicknessFactor", 0.0),
            sigma_a=[-math.log(max(c, 1e-9)) / distance  # [:3]: the importer appends an alpha to it
                     for c in vol.get("attenuationColor", [1.0] * 3)[:3]])

    BlenderCamera.create, BlenderMaterial.create = staticmethod(camera), staticmethod(material)


def gltf_bsdf(mat):
    """Rewire `mat`, as the importer built it, into the glTF BRDF as Lancer evaluates it."""
    nt = mat.node_tree
    P = next((n for n in nt.nodes if n.type == "BSDF_PRINCIPLED"), None)
    out = next((n for n in nt.nodes if n.type == "OUTPUT_MATERIAL"), None)
    if P is None or out is None or "ior" not in mat:
        return warn(f"material {mat.name} is not glTF metallic-roughness: left as imported")
    given = lambda name: P.inputs[name].is_linked or P.inputs[name].default_value > 0.0

    def link(src, dst):  # src: a socket, a value, or the name of an input of P (its texture or value)
        if isinstance(src, str):
            src = P.inputs[src].links[0].from_socket if P.inputs[src].is_linked else P.inputs[src].default_value
            if dst.name == "Normal" and not isinstance(src, bpy.types.NodeSocket):
                return  # no normal map: the shading normal
        if isinstance(src, bpy.types.NodeSocket):
            nt.links.new(src, dst)
        else:
            dst.default_value = src

    def node(kind, *same, **inputs):  # same: inputs fed as P's inputs of those names are
        n = nt.nodes.new(kind)
        for name, src in [(s, s) for s in same] + [(k.replace("_", " "), v) for k, v in inputs.items()]:
            link(src, n.inputs[name])
        return n

    def math(op, *operands):
        n = nt.nodes.new("ShaderNodeMath")
        n.operation = op
        for i, x in enumerate(operands):
            link(x, n.inputs[i])
        return n.outputs[0]

    def mix(fac, a, b):  # fac None: a + b, else (1 - fac) a + fac b; a or b None: no closure
        m = nt.nodes.new("ShaderNodeAddShader" if fac is None else "ShaderNodeMixShader")
        if fac is not None:
            link(fac, m.inputs[0])
        for i, shader in ((-2, a), (-1, b)):
            if shader is not None:
                nt.links.new(shader.outputs[0], m.inputs[i])
        return m

    ior, spec = mat["ior"], mat["specular"]
    f0 = min(((ior - 1) / (ior + 1)) ** 2 * mat["specular_color"], 1.0) * spec
    # Lancer's 1 - F(V.H) averaged over cosine-weighted light directions is 1 - f0 - (spec - f0)
    # G(N.V), G(mu) = 0.0285 (1 - mu)^2.5 (a fit, within 0.001); Layer Weight Facing = 1 - |N.V|.
    facing = node("ShaderNodeLayerWeight", "Normal", Blend=0.5).outputs["Facing"]
    loss = math("MULTIPLY_ADD", math("POWER", facing, 2.5), 0.0285 * (spec - f0), f0)
    lambert = node("ShaderNodeBsdfDiffuse", "Normal", Color="Base Color", Roughness=0.0)
    gloss = node("ShaderNodeBsdfPrincipled", "Roughness", "Normal", Base_Color=(0, 0, 0, 1),
                 Specular=f0 / 0.08, Specular_Tint=0.0)
    surface = mix(None, mix(loss, lambert, None), gloss)
    backfacing = nt.nodes.new("ShaderNodeNewGeometry").outputs["Backfacing"]
    if given("Transmission") and not mat["thin"]:
        surface = mix("Transmission", surface,
                      node("ShaderNodeBsdfPrincipled", "Base Color", "Roughness", "IOR", "Normal", Transmission=1.0))
    elif given("Transmission"):  # both sides face air: Fresnel of ior from both sides (the node inverts it)
        if P.inputs["Roughness"].is_linked or P.inputs["Roughness"].default_value > 0.03:
            warn(f"material {mat.name}: this rough thin wall transmits unblurred")
        eta = math("POWER", ior, math("MULTIPLY_ADD", backfacing, -2.0, 1.0))
        wall = node("ShaderNodeBsdfGlossy", "Roughness", "Normal")
        wall.distribution = "GGX"
        wall = mix(node("ShaderNodeFresnel", "Normal", IOR=eta).outputs[0],
                   node("ShaderNodeBsdfTransparent", Color="Base Color"), wall)
        surface = mix("Transmission", surface, wall)
    if given("Metallic"):
        surface = mix("Metallic", surface, node("ShaderNodeBsdfPrincipled", "Base Color", "Roughness", "Normal",
                                                Metallic=1.0))
    if P.inputs["Emission"].is_linked or max(mat["emission"]) > 0.0:  # from the front side only
        front = math("MULTIPLY_ADD", backfacing, -1.0, 1.0)
        if P.inputs["Emission"].is_linked:  # a texture: the importer's factor x texture and strength
            strength = math("MULTIPLY", front, "Emission Strength")
            emission = node("ShaderNodeEmission", Color="Emission", Strength=strength)
        else:  # the glTF radiance itself, emissiveFactor x emissiveStrength
            emission = node("ShaderNodeEmission", Color=(*mat["emission"], 1.0), Strength=front)
        surface = mix(None, surface, emission)
    nt.links.new(surface.outputs[0], out.inputs["Surface"])
    for old in list(out.inputs["Volume"].links):
        nt.links.remove(old)
    sigma = max(mat["sigma_a"])
    if not mat["thin"] and sigma > 0.0:  # Cycles absorbs (1 - Color) x Density per unit length
        colour = (*[1.0 - s / sigma for s in mat["sigma_a"]], 1.0)
        nt.links.new(node("ShaderNodeVolumeAbsorption", Color=colour, Density=sigma).outputs[0], out.inputs["Volume"])


def build_scene(a):
    scene = bpy.context.scene
    for obj in list(bpy.data.objects):  # the factory cube, light and camera
        bpy.data.objects.remove(obj, do_unlink=True)
    if not os.path.isfile(a.scene):
        fail(f"{a.scene}: no such file")
    tag_imported_data()
    bpy.ops.import_scene.gltf(filepath=os.path.abspath(a.scene), convert_lighting_mode="COMPAT")
    for obj in scene.objects:
        if obj.type == "MESH" and not obj.data.materials:  # glTF's default material, as Lancer
            obj.data.materials.append(bpy.data.materials.get("gltf default") or default_material())
        elif obj.type == "LIGHT":
            obj.data.shadow_soft_size = 0.0
            if obj.data.type == "SPOT":
                warn(f"spot light {obj.name}: Blender's cone falloff is not glTF's")
            elif obj.data.type == "SUN":
                obj.data.angle = 0.0
    for mat in {s.material for o in scene.objects for s in o.material_slots if s.material}:
        gltf_bsdf(mat)

    cams = [o for o in scene.objects if o.type == "CAMERA" and o.data.get("gltf_camera") == a.camera]
    if not cams or cams[0].data.type != "PERSP":
        fail(f"--camera {a.camera}: the file has no perspective camera {a.camera} on a node")
    scene.camera = min(cams, key=lambda o: o.data["order"])  # on several nodes: the first imported
    cam = scene.camera.data
    cam.sensor_fit = "VERTICAL"  # yfov spans the image height, whatever the aspect ratio
    if abs(cam.angle_y - cam["yfov"]) > 1e-6:
        warn(f"camera angle_y {cam.angle_y} is not the yfov {cam['yfov']}: set")
        cam.angle_y = cam["yfov"]
    if cam.get("aperture", 0.0) > 0.0:  # Cycles' lens radius is lens / (2 fstop), lens in mm
        cam.dof.use_dof, cam.dof.aperture_blades = True, 0
        cam.dof.focus_distance = cam.get("focusDistance", 1e9)  # along the view axis; none: infinity
        cam.dof.aperture_fstop = cam.lens * 1e-3 / (2.0 * cam["aperture"])

    scene.world = scene.world or bpy.data.worlds.new("World")
    scene.world.use_nodes, scene.world.cycles.sampling_method = True, "NONE"
    background = next(n for n in scene.world.node_tree.nodes if n.type == "BACKGROUND")
    background.inputs["Color"].default_value, background.inputs["Strength"].default_value = (0, 0, 0, 1), 0.0
    return scene


def default_material():
    mat = bpy.data.materials.new("gltf default")
    mat.use_nodes = True
    for name, value in (("Base Color", (1, 1, 1, 1)), ("Metallic", 1.0), ("Roughness", 1.0)):
        mat.node_tree.nodes["Principled BSDF"].inputs[name].default_value = value
    return tag(mat, emission=[0.0] * 3, ior=1.5, specular=1.0, specular_color=1.0, thin=True, sigma_a=[0.0] * 3)


def configure(scene, a):
    r, c, v, im = scene.render, scene.cycles, scene.view_settings, scene.render.image_settings
    r.engine, r.resolution_x, r.resolution_y, r.resolution_percentage = "CYCLES", a.width, a.height, 100
    r.pixel_aspect_x = r.pixel_aspect_y = 1.0
    r.film_transparent = r.use_motion_blur = r.use_border = False
    r.threads_mode = "FIXED" if a.threads > 0 else "AUTO"
    if a.threads > 0:
        r.threads = a.threads
    im.file_format, im.color_mode, im.color_depth, im.exr_codec = "OPEN_EXR", "RGBA", "32", "ZIP"
    r.filepath, r.use_file_extension = os.path.abspath(a.output), False
    if os.path.exists(r.filepath):  # so that a file found afterwards is this render's
        os.remove(r.filepath)
    c.device, c.samples, c.seed, c.use_animated_seed = "CPU", a.spp, a.seed, False
    c.use_adaptive_sampling = c.use_denoising = False
    c.sample_clamp_direct = c.sample_clamp_indirect = c.blur_glossy = c.light_sampling_threshold = 0.0
    c.caustics_reflective = c.caustics_refractive = True
    c.max_bounces = c.diffuse_bounces = c.glossy_bounces = c.transmission_bounces = a.max_bounces
    c.volume_bounces = c.transparent_max_bounces = a.max_bounces
    c.pixel_filter_type, c.filter_width, c.film_exposure = "BOX", 1.0, 1.0
    v.view_transform, v.look, v.exposure, v.gamma = "Standard", "None", 0.0, 1.0


def main():
    p = argparse.ArgumentParser(prog="cycles_render.py")
    p.error = fail
    p.add_argument("--scene", required=True)
    p.add_argument("--output", required=True)
    for name, default in (("width", 256), ("height", 256), ("spp", 256), ("max-bounces", 64), ("threads", 0),
                          ("seed", 0), ("camera", 0)):
        p.add_argument("--" + name, type=int, default=default)
    a = p.parse_args(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else [])
    if min(a.width, a.height, a.spp) < 1 or min(a.max_bounces, a.threads, a.camera) < 0:
        fail("--width, --height and --spp must be positive, --max-bounces, --threads and --camera not negative")
    scene = build_scene(a)
    configure(scene, a)
    start = time.perf_counter()
    bpy.ops.render.render(write_still=True)
    seconds = time.perf_counter() - start
    if not os.path.isfile(scene.render.filepath):
        fail(f"{scene.render.filepath} was not written")
    report = {"render_seconds": round(seconds, 3), "width": a.width, "height": a.height, "spp": a.spp,
              "max_bounces": a.max_bounces, "threads": scene.render.threads}
    print("cycles_render: " + json.dumps(report), flush=True)


try:
    main()
except SystemExit:
    raise
except Exception as e:  # an import or render failure
    fail(f"{type(e).__name__}: {e}")

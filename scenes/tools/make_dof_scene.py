#!/usr/bin/env python3
"""Writes scenes/cornell-box-dof.gltf: the Cornell box with three spheres at different
depths and a thin-lens camera focused on the middle one (depth of field).

The box, light, camera position and sphere tessellation come from
scripts/make_cornell_box.py (imported, not copied). The lens is Lancer's camera
convention (src/scene/scene.h, CameraDesc): the camera's `extras` hold
{"aperture": lens radius, "focusDistance": distance to the plane in focus along the
view axis}, both in metres. Blur on the image, as an angle, is
2 * aperture * |1/depth - 1/focusDistance| radians (thin lens), so with the numbers
below the front sphere spreads over about 10 pixels of a 512-pixel image, the back
one about 7, and the back wall about 10; the middle sphere stays sharp.

Python 3 standard library only; the output is the same on every run.
Usage: python3 scenes/tools/make_dof_scene.py [output_dir]   (default: scenes/)
"""

import importlib.util
import json
import os
import sys

sys.dont_write_bytecode = True  # no __pycache__ beside the scripts
HERE = os.path.dirname(os.path.abspath(__file__))


def load_cornell_module():
    path = os.path.join(HERE, "..", "..", "scripts", "make_cornell_box.py")
    spec = importlib.util.spec_from_file_location("make_cornell_box", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


# Sphere centres in millimetres (the Cornell data's unit), radius 80 mm, resting on
# the floor on a diagonal from the front left (red wall side, x large) to the back right.
SPHERE_RADIUS_M = 0.08
SPHERES = [
    ("front_sphere", "yellow_plastic", (400.0, 80.0, 120.0)),
    ("middle_sphere", "mirror", (265.0, 80.0, 290.0)),
    ("back_sphere", "blue_matte", (125.0, 80.0, 470.0)),
]
# The camera sits at z = -0.8 m looking along +z, so depth along the view axis is
# z + 0.8: focused on the middle sphere's centre.
FOCUS_DISTANCE_M = 0.29 + 0.8
APERTURE_RADIUS_M = 0.04
# The ceiling light grows LIGHT_SCALE times in x and z about its centre and its radiance
# falls by LIGHT_SCALE^2, so the light's power and the box's brightness stay the same.
# A larger, dimmer light makes the highlights of the glossy and mirror spheres larger
# and dimmer, which is what path tracing needs to light the walls through them with
# little noise (the published small light turns them into sparkles at a few hundred
# samples per pixel).
LIGHT_SCALE = 2.0


def dof_materials(cornell):
    mats = cornell.materials(with_spheres=True)  # box materials, mirror, glass
    mats.append({"name": "yellow_plastic",
                 "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.55, 0.08, 1.0], "metallicFactor": 0.0,
                                          "roughnessFactor": 0.25}})
    mats.append({"name": "blue_matte",
                 "pbrMetallicRoughness": {"baseColorFactor": [0.1, 0.22, 0.6, 1.0], "metallicFactor": 0.0,
                                          "roughnessFactor": 1.0}})
    return mats


def build():
    cornell = load_cornell_module()
    meshes = cornell.box_meshes(with_blocks=False)
    for mesh in meshes:
        if mesh.name == "light":
            cx = sum(p[0] for p in mesh.positions) / len(mesh.positions)
            cz = sum(p[2] for p in mesh.positions) / len(mesh.positions)
            mesh.positions = [(cornell.f32(cx + LIGHT_SCALE * (p[0] - cx)), p[1], cornell.f32(cz + LIGHT_SCALE * (p[2] - cz)))
                              for p in mesh.positions]
    for name, material, centre in SPHERES:
        meshes.append(cornell.uv_sphere(name, material, centre, SPHERE_RADIUS_M, cornell.SPHERE_SLICES,
                                        cornell.SPHERE_STACKS))
    mats = [m for m in dof_materials(cornell) if m["name"] != "glass"]
    for m in mats:
        if m["name"] == "light":
            strength = m["extensions"]["KHR_materials_emissive_strength"]
            strength["emissiveStrength"] /= LIGHT_SCALE * LIGHT_SCALE
    gltf = json.loads(cornell.build_gltf(meshes, mats))
    gltf["asset"]["generator"] = "Lancer scenes/tools/make_dof_scene.py (Cornell Box Data, metres)"
    gltf["scenes"][0]["name"] = "cornell_box_dof"
    gltf["cameras"][0]["extras"] = {"aperture": APERTURE_RADIUS_M, "focusDistance": FOCUS_DISTANCE_M}
    return json.dumps(gltf, indent=2) + "\n"


def main():
    out_dir = sys.argv[1] if len(sys.argv) > 1 else os.path.join(HERE, "..")
    os.makedirs(out_dir, exist_ok=True)
    path = os.path.join(out_dir, "cornell-box-dof.gltf")
    with open(path, "w", encoding="ascii", newline="\n") as f:
        f.write(build())
    print("wrote", os.path.normpath(path))


if __name__ == "__main__":
    main()

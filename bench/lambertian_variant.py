#!/usr/bin/python3
"""Writes a copy of a glTF scene whose every material is a pure Lambertian reflector, for
comparisons with Blender Cycles whose material models would otherwise differ from penumbra's.

Not a test and not part of the build: a benchmark helper. Usage:

    bench/lambertian_variant.py [--without-transmissive] SCENE.gltf OUT.gltf

Each material keeps its base colour (factor and texture) and its emission; it loses its metallic
and specular reflection (metallicFactor 0, roughnessFactor 1, KHR_materials_specular
specularFactor 0: pure Lambertian, docs/light-paths.md), its transmission, volume and index of
refraction, and its alpha mask (made opaque; a masked base colour texture is replaced by mid
grey, since Cycles' image node with its alpha unused premultiplies the colour by alpha). Why:
Blender 3.4's Principled BSDF (which the peer harness keeps for rough dielectrics) adds its
specular layer on top of an undiminished diffuse one, where glTF's dielectric takes the diffuse
light the Fresnel term leaves; and the harness's conversion to a Diffuse closure drops alpha
masks. With only Lambertian materials both renderers compute the same integral, so a difference
is the lights', the geometry's or the textures'.

With --without-transmissive, the nodes whose mesh has a transmissive material (glass) lose the
mesh instead: made Lambertian, a pane would be an opaque white board.

The copy's buffers, images and the environment recorded in `scenes[0].extras` point back to the
original files by relative paths, so it can be written anywhere on the same file system.
"""
import json
import sys

from gltf_copy import rebase_files, write_document

# The base colour of a material whose texture had an alpha mask, which the copy drops.
MASKED_BASE_COLOR = [0.5, 0.5, 0.5, 1.0]

DROPPED_EXTENSIONS = ("KHR_materials_transmission", "KHR_materials_volume", "KHR_materials_ior",
                      "KHR_materials_specular", "KHR_materials_clearcoat", "KHR_materials_sheen")


def lambertian(material):
    pbr = material.setdefault("pbrMetallicRoughness", {})
    pbr["metallicFactor"] = 0.0
    pbr["roughnessFactor"] = 1.0
    pbr.pop("metallicRoughnessTexture", None)
    extensions = material.setdefault("extensions", {})
    for name in DROPPED_EXTENSIONS:
        extensions.pop(name, None)
    extensions["KHR_materials_specular"] = {"specularFactor": 0.0}
    # Cycles' image node, with its alpha output unused (the harness's Diffuse closure), gives the
    # colour premultiplied by alpha: a masked texture's cut-out texels would differ.
    if material.pop("alphaMode", "OPAQUE") != "OPAQUE" and "baseColorTexture" in pbr:
        del pbr["baseColorTexture"]
        pbr["baseColorFactor"] = MASKED_BASE_COLOR
    material.pop("alphaCutoff", None)


def transmits(material):
    return "KHR_materials_transmission" in material.get("extensions", {})


def remove_transmissive_meshes(document):
    """Takes the mesh off every node whose mesh has a transmissive primitive."""
    materials = document.get("materials", [])
    glass = {i for i, mesh in enumerate(document.get("meshes", []))
             if any("material" in p and transmits(materials[p["material"]])
                    for p in mesh["primitives"])}
    for node in document.get("nodes", []):
        if node.get("mesh") in glass:
            del node["mesh"]


def main():
    args = sys.argv[1:]
    without_transmissive = "--without-transmissive" in args
    args = [a for a in args if a != "--without-transmissive"]
    if len(args) != 2:
        raise SystemExit("usage: lambertian_variant.py [--without-transmissive] SCENE.gltf OUT.gltf")
    source, out = args
    with open(source) as f:
        document = json.load(f)
    rebase_files(document, source, out)
    if without_transmissive:
        remove_transmissive_meshes(document)
    for material in document.get("materials", []):
        lambertian(material)
    used = set(document.get("extensionsUsed", [])) - set(DROPPED_EXTENSIONS)
    document["extensionsUsed"] = sorted(used | {"KHR_materials_specular"})
    if "extensionsRequired" in document:
        document["extensionsRequired"] = [e for e in document["extensionsRequired"]
                                          if e not in DROPPED_EXTENSIONS]
    write_document(document, out)
    print("%s: %d materials made Lambertian" % (out, len(document.get("materials", []))))


if __name__ == "__main__":
    main()

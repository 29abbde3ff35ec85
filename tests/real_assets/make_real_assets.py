# Builds five small animated scenes in Blender and exports each as FBX,
# Collada, glTF (binary) and an OBJ sequence twin (one OBJ per frame, the same
# animation evaluated by Blender), into OUTDIR/<scene>/, for the end-to-end
# tests of tests/real_assets/.
#
#   blender -b --factory-startup --python tests/real_assets/make_real_assets.py -- OUTDIR
#
# Written for Blender 3.4 (Debian 12), which still has its Collada exporter
# (wm.collada_export); a Blender without it skips the .dae files and says so.
#
# The scenes, all frames 0 to 16 at 24 fps, Blender world coordinates (Z up,
# metres), built from triangles so that every format keeps the same faces:
#   rigid_box       a closed 1 m cube (8 vertices, 12 triangles), translated
#                   and rotated by object keyframes. Flat shaded.
#   rigid_cylinder  a closed cylinder (16 segments, radius 0.3 m, 1 m tall,
#                   caps fanned from a centre vertex: 34 vertices, 64
#                   triangles), moved rigidly. Smooth sides, sharp rims
#                   (auto smooth 30 degrees), so the caps' normals split.
#   bent_tube       a closed 8-sided tube (radius 0.15 m, 2 m tall, 9 rings,
#                   capped: 74 vertices, 144 triangles) skinned to a two-bone
#                   armature; the upper bone bends 45 degrees about X while the
#                   armature slides along X. Flat shaded.
#   garment         a flared skirt of four planar trapezoid panels (front,
#                   right, back, left; 5 x 6 vertices each, 120 vertices, 160
#                   triangles), each panel its own mesh island: the panels
#                   meet at four vertical side seams whose vertices coincide
#                   bit for bit but are not merged. Skinned to a waist bone
#                   and a hem bone with weights that depend on the row only,
#                   so coincident seam vertices move identically; the hem
#                   sways about X and the armature turns about Z and slides.
#   box_through_box two 1 m cubes as two objects (8 vertices, 12 triangles
#                   each): "wall" stands still, "mover" turns and slides
#                   through it along X, so there are collisions and
#                   intersections in generic position (no touching features).
# The first four have no collision and no intersection.
#
# The exporters keep their defaults for axes: FBX, Collada, glTF and OBJ all
# come back Y up, Blender's (x, y, z) read as (x, z, -y) (see
# tests/io_assimp/blender_rig_test.cpp), so the OBJ twin and the animated
# files hold the same world positions. Blender's OBJ exporter prints six
# decimals, so the twin differs from the animated files by up to 5e-7 m.
# The FBX keeps a key on every frame (no curve simplification): assimp
# interpolates rotations between keys differently from Blender's Euler curves.
# FBX and Collada stamp their creation time, so reruns differ in those bytes
# only; glTF and OBJ files are byte-identical from run to run.
import math
import os
import sys

import bpy

FPS = 24
FRAME_END = 16


def out_dir():
    argv = sys.argv
    args = argv[argv.index("--") + 1:] if "--" in argv else []
    if len(args) != 1:
        raise SystemExit("usage: blender -b --factory-startup --python make_real_assets.py -- OUTDIR")
    return args[0]


def clear_scene():
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj, do_unlink=True)
    for collection in (bpy.data.meshes, bpy.data.armatures, bpy.data.actions, bpy.data.materials):
        for block in list(collection):
            collection.remove(block)
    scene = bpy.context.scene
    scene.render.fps = FPS
    scene.frame_start = 0
    scene.frame_end = FRAME_END
    scene.frame_set(0)
    return scene


def mesh_object(scene, name, verts, faces, smooth=False, auto_smooth_degrees=None):
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(verts, [], faces)
    mesh.update()
    for poly in mesh.polygons:
        poly.use_smooth = smooth
    if auto_smooth_degrees is not None:
        mesh.use_auto_smooth = True
        mesh.auto_smooth_angle = math.radians(auto_smooth_degrees)
    obj = bpy.data.objects.new(name, mesh)
    scene.collection.objects.link(obj)
    return obj


def linear_keys(id_with_animation):
    for fc in id_with_animation.animation_data.action.fcurves:
        for key in fc.keyframe_points:
            key.interpolation = "LINEAR"


def key_object_motion(obj, keys):
    """keys: (frame, location, rotation in degrees XYZ)."""
    obj.rotation_mode = "XYZ"
    for frame, location, degrees in keys:
        obj.location = location
        obj.rotation_euler = tuple(math.radians(d) for d in degrees)
        obj.keyframe_insert("location", frame=frame)
        obj.keyframe_insert("rotation_euler", frame=frame)
    linear_keys(obj)


def armature(scene, name, bones):
    """bones: (name, head, tail, parent name or None), in order."""
    data = bpy.data.armatures.new(name)
    arm = bpy.data.objects.new(name, data)
    scene.collection.objects.link(arm)
    bpy.context.view_layer.objects.active = arm
    bpy.ops.object.mode_set(mode="EDIT")
    for bone_name, head, tail, parent in bones:
        bone = data.edit_bones.new(bone_name)
        bone.head, bone.tail = head, tail
        if parent:
            bone.parent = data.edit_bones[parent]
            bone.use_connect = tuple(data.edit_bones[parent].tail) == tuple(head)
    bpy.ops.object.mode_set(mode="OBJECT")
    return arm


def skin(obj, arm, weights):
    """weights: per vertex, a dict bone name -> weight."""
    groups = {}
    for v, bone_weights in enumerate(weights):
        for bone, w in bone_weights.items():
            if w <= 0:
                continue
            if bone not in groups:
                groups[bone] = obj.vertex_groups.new(name=bone)
            groups[bone].add([v], w, "REPLACE")
    obj.parent = arm
    mod = obj.modifiers.new("Armature", "ARMATURE")
    mod.object = arm


def key_bone_rotation(arm, bone, keys):
    """keys: (frame, rotation in degrees XYZ)."""
    pose_bone = arm.pose.bones[bone]
    pose_bone.rotation_mode = "XYZ"
    for frame, degrees in keys:
        pose_bone.rotation_euler = tuple(math.radians(d) for d in degrees)
        pose_bone.keyframe_insert("rotation_euler", frame=frame)
    linear_keys(arm)


def cube(scene, name):
    h = 0.5
    verts = [(x, y, z) for z in (-h, h) for y in (-h, h) for x in (-h, h)]
    # 0..3 bottom (z = -h), 4..7 top; index = x + 2y + 4z. Outward triangles.
    faces = [(0, 2, 3), (0, 3, 1),  # bottom, -Z
             (4, 5, 7), (4, 7, 6),  # top, +Z
             (0, 1, 5), (0, 5, 4),  # -Y
             (2, 6, 7), (2, 7, 3),  # +Y
             (0, 4, 6), (0, 6, 2),  # -X
             (1, 3, 7), (1, 7, 5)]  # +X
    return mesh_object(scene, name, verts, faces)


def rigid_box(scene):
    box = cube(scene, "rigid_box")
    key_object_motion(box, [(0, (0.0, 0.0, 0.5), (0, 0, 0)),
                            (FRAME_END, (1.5, 0.5, 1.0), (20, 10, 90))])
    return box


def box_through_box(scene):
    wall = cube(scene, "wall")
    wall.location = (0.0, 0.0, 0.5)
    wall.rotation_euler = (0.0, 0.0, math.radians(10))
    mover = cube(scene, "mover")
    key_object_motion(mover, [(0, (-1.6, 0.2, 0.63), (15, 25, 40)),
                              (FRAME_END, (1.7, -0.1, 0.55), (35, -20, 130))])
    return [wall, mover]


def rigid_cylinder(scene):
    segments, r, h = 16, 0.3, 0.5
    verts = []
    for z in (-h, h):
        for k in range(segments):
            a = 2 * math.pi * k / segments
            verts.append((r * math.cos(a), r * math.sin(a), z))
    bottom_centre, top_centre = len(verts), len(verts) + 1
    verts += [(0.0, 0.0, -h), (0.0, 0.0, h)]
    faces = []
    for k in range(segments):
        a, b = k, (k + 1) % segments
        faces.append((a, b, b + segments))
        faces.append((a, b + segments, a + segments))
        faces.append((bottom_centre, b, a))
        faces.append((top_centre, a + segments, b + segments))
    cylinder = mesh_object(scene, "rigid_cylinder", verts, faces, smooth=True, auto_smooth_degrees=30)
    key_object_motion(cylinder, [(0, (0.0, 0.0, 0.5), (0, 0, 0)),
                                 (FRAME_END, (-1.0, 1.0, 1.2), (60, -15, 45))])
    return cylinder


def bent_tube(scene):
    arm = armature(scene, "tube_rig", [("lower", (0, 0, 0), (0, 0, 1), None),
                                       ("upper", (0, 0, 1), (0, 0, 2), "lower")])
    sides, rings, r = 8, 9, 0.15
    verts, weights = [], []
    for ring in range(rings):
        z = 0.25 * ring
        upper = min(1.0, max(0.0, (z - 0.75) / 0.5))  # blend over the rings at 0.75 .. 1.25 m
        for k in range(sides):
            a = 2 * math.pi * k / sides
            verts.append((r * math.cos(a), r * math.sin(a), z))
            weights.append({"lower": 1.0 - upper, "upper": upper})
    bottom_centre, top_centre = len(verts), len(verts) + 1
    verts += [(0.0, 0.0, 0.0), (0.0, 0.0, 0.25 * (rings - 1))]
    weights += [{"lower": 1.0}, {"upper": 1.0}]
    faces = []
    for ring in range(rings - 1):
        for k in range(sides):
            a, b = ring * sides + k, ring * sides + (k + 1) % sides
            faces.append((a, b, b + sides))
            faces.append((a, b + sides, a + sides))
    top = (rings - 1) * sides
    for k in range(sides):
        faces.append((bottom_centre, (k + 1) % sides, k))
        faces.append((top_centre, top + k, top + (k + 1) % sides))
    tube = mesh_object(scene, "bent_tube", verts, faces)
    skin(tube, arm, weights)
    for frame, x in ((0, 0.0), (FRAME_END, 0.5)):
        arm.location = (x, 0.0, 0.0)
        arm.keyframe_insert("location", frame=frame)
    key_bone_rotation(arm, "upper", [(0, (0, 0, 0)), (FRAME_END, (45, 0, 0))])
    return tube


def garment(scene):
    arm = armature(scene, "garment_rig", [("waist", (0, 0, 1.0), (0, 0, 0.6), None),
                                          ("hem", (0, 0, 0.6), (0, 0, 0.2), "waist")])
    columns, rows = 5, 6
    top_z, bottom_z, top_half, bottom_half = 1.0, 0.2, 0.3, 0.45

    def corner(c, row):
        """Seam line c (0: -x-y, 1: +x-y, 2: +x+y, 3: -x+y) at a row, computed once."""
        t = row / (rows - 1)
        half = top_half + (bottom_half - top_half) * t
        z = top_z + (bottom_z - top_z) * t
        sx, sy = ((-1, -1), (1, -1), (1, 1), (-1, 1))[c]
        return (sx * half, sy * half, z)

    seams = [[corner(c, row) for row in range(rows)] for c in range(4)]
    verts, weights, faces = [], [], []
    for panel in range(4):  # front (-y), right (+x), back (+y), left (-x)
        c0, c1 = panel, (panel + 1) % 4
        base = len(verts)
        for row in range(rows):
            p0, p1 = seams[c0][row], seams[c1][row]
            for col in range(columns):
                if col == 0:
                    p = p0
                elif col == columns - 1:
                    p = p1
                else:
                    s = col / (columns - 1)
                    p = tuple(a + (b - a) * s for a, b in zip(p0, p1))
                verts.append(p)
                hem = row / (rows - 1)
                weights.append({"waist": 1.0 - hem, "hem": hem})
        for row in range(rows - 1):
            for col in range(columns - 1):
                a = base + row * columns + col
                faces.append((a, a + columns, a + columns + 1))
                faces.append((a, a + columns + 1, a + 1))
    skirt = mesh_object(scene, "garment", verts, faces, smooth=True)
    skin(skirt, arm, weights)
    arm.rotation_mode = "XYZ"
    for frame, x, turn in ((0, 0.0, 0.0), (FRAME_END, 0.4, 30.0)):
        arm.location = (x, 0.0, 0.0)
        arm.rotation_euler = (0.0, 0.0, math.radians(turn))
        arm.keyframe_insert("location", frame=frame)
        arm.keyframe_insert("rotation_euler", frame=frame)
    key_bone_rotation(arm, "hem", [(0, (0, 0, 0)), (FRAME_END // 2, (15, 0, 0)), (FRAME_END, (-10, 0, 5))])
    return skirt


def export(scene, meshes, directory, name):
    os.makedirs(directory, exist_ok=True)
    scene.frame_set(0)
    bpy.ops.object.select_all(action="SELECT")
    base = os.path.join(directory, name)
    bpy.ops.export_scene.gltf(filepath=base + ".glb", export_format="GLB", export_animations=True,
                              export_skins=True, export_morph=False, export_materials="NONE",
                              export_normals=True, export_texcoords=False, export_force_sampling=True)
    bpy.ops.export_scene.fbx(filepath=base + ".fbx", bake_anim=True, add_leaf_bones=False,
                             apply_scale_options="FBX_SCALE_ALL", bake_anim_use_all_actions=False,
                             bake_anim_use_nla_strips=False, bake_anim_simplify_factor=0.0,
                             use_mesh_modifiers=False)
    if "collada_export" in dir(bpy.ops.wm):  # hasattr is always true on bpy.ops
        bpy.ops.wm.collada_export(filepath=base + ".dae", include_animations=True, include_armatures=True,
                                  sampling_rate=1, keep_keyframes=False,
                                  export_animation_type_selection="sample")
    else:
        print("this Blender has no Collada exporter: no", base + ".dae")
    # The twin: the evaluated mesh of each frame, world coordinates, shared
    # vertices (one `v` per Blender vertex), no normals or texture coordinates.
    bpy.ops.object.select_all(action="DESELECT")
    for mesh in meshes:
        mesh.select_set(True)
    for frame in range(scene.frame_start, scene.frame_end + 1):
        scene.frame_set(frame)
        bpy.ops.wm.obj_export(filepath=os.path.join(directory, f"obj_{frame:04d}.obj"),
                              export_animation=False, export_selected_objects=True, apply_modifiers=True,
                              export_eval_mode="DAG_EVAL_VIEWPORT", export_uv=False, export_normals=False,
                              export_colors=False, export_materials=False, export_triangulated_mesh=True,
                              export_object_groups=False, export_material_groups=False,
                              export_vertex_groups=False, export_smooth_groups=False)
    scene.frame_set(0)


def main():
    out = out_dir()
    for build in (rigid_box, rigid_cylinder, bent_tube, garment, box_through_box):
        scene = clear_scene()
        meshes = build(scene)
        if not isinstance(meshes, list):
            meshes = [meshes]
        scene.frame_set(0)
        export(scene, meshes, os.path.join(out, build.__name__), build.__name__)
        print("exported", build.__name__, "into", os.path.join(out, build.__name__))


main()

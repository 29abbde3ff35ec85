# Builds a tiny animated rig in Blender and exports it as glTF (binary), FBX
# and Collada into OUTDIR, with Blender's own evaluated world positions at a
# few frames as CSV, for the cross-format tests of the assimp reader.
#
#   blender -b --factory-startup --python tests/io_assimp/export_rig.py -- OUTDIR
#
# The rig: a 4-sided tube (0.4 m wide, 2 m tall, 5 rings, 20 vertices) skinned
# to a two-bone armature (lower bone: rings 0-1, both bones 50/50: ring 2, upper
# bone: rings 3-4). The armature object moves along X and the upper bone bends
# 60 degrees about X; frames 0 to 24 at 24 fps (0 to 1 s).
#
# rig_positions.csv: frame, seconds, vertex (Blender's order), x, y, z in
# Blender world coordinates (Z up, metres), at frames 0, 6, 12, 18, 24.
import math
import os
import sys

import bpy

FPS = 24
FRAME_END = 24
CSV_FRAMES = (0, 6, 12, 18, 24)


def out_dir():
    argv = sys.argv
    args = argv[argv.index("--") + 1:] if "--" in argv else []
    if len(args) != 1:
        raise SystemExit("usage: blender -b --factory-startup --python export_rig.py -- OUTDIR")
    return args[0]


def build():
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj, do_unlink=True)
    scene = bpy.context.scene
    scene.render.fps = FPS
    scene.frame_start = 0
    scene.frame_end = FRAME_END

    arm_data = bpy.data.armatures.new("rig")
    arm = bpy.data.objects.new("rig", arm_data)
    scene.collection.objects.link(arm)
    bpy.context.view_layer.objects.active = arm
    bpy.ops.object.mode_set(mode="EDIT")
    lower = arm_data.edit_bones.new("lower")
    lower.head, lower.tail = (0, 0, 0), (0, 0, 1)
    upper = arm_data.edit_bones.new("upper")
    upper.head, upper.tail = (0, 0, 1), (0, 0, 2)
    upper.parent = lower
    upper.use_connect = True
    bpy.ops.object.mode_set(mode="OBJECT")

    half = 0.2
    corners = [(-half, -half), (half, -half), (half, half), (-half, half)]
    verts = [(x, y, 0.5 * ring) for ring in range(5) for (x, y) in corners]
    faces = []
    for ring in range(4):
        for c in range(4):
            a, b = ring * 4 + c, ring * 4 + (c + 1) % 4
            faces.append((a, b, b + 4))
            faces.append((a, b + 4, a + 4))
    faces.append((0, 2, 1))
    faces.append((0, 3, 2))
    faces.append((16, 17, 18))
    faces.append((16, 18, 19))
    mesh = bpy.data.meshes.new("tube")
    mesh.from_pydata(verts, [], faces)
    mesh.update()
    tube = bpy.data.objects.new("tube", mesh)
    scene.collection.objects.link(tube)
    tube.parent = arm
    g_lower = tube.vertex_groups.new(name="lower")
    g_upper = tube.vertex_groups.new(name="upper")
    for v in range(20):
        ring = v // 4
        if ring <= 1:
            g_lower.add([v], 1.0, "REPLACE")
        elif ring == 2:
            g_lower.add([v], 0.5, "REPLACE")
            g_upper.add([v], 0.5, "REPLACE")
        else:
            g_upper.add([v], 1.0, "REPLACE")
    mod = tube.modifiers.new("Armature", "ARMATURE")
    mod.object = arm

    for frame, x in ((0, 0.0), (24, 1.0)):
        arm.location = (x, 0.0, 0.0)
        arm.keyframe_insert("location", frame=frame)
    pose_upper = arm.pose.bones["upper"]
    pose_upper.rotation_mode = "XYZ"
    for frame, angle in ((0, 0.0), (24, 60.0)):
        pose_upper.rotation_euler = (math.radians(angle), 0.0, 0.0)
        pose_upper.keyframe_insert("rotation_euler", frame=frame)
    for fc in arm.animation_data.action.fcurves:
        for key in fc.keyframe_points:
            key.interpolation = "LINEAR"
    return scene, arm, tube


def write_csv(path, scene, tube):
    with open(path, "w") as f:
        f.write("frame,seconds,vertex,x,y,z\n")
        for frame in CSV_FRAMES:
            scene.frame_set(frame)
            depsgraph = bpy.context.evaluated_depsgraph_get()
            ev = tube.evaluated_get(depsgraph)
            m = ev.matrix_world.copy()
            mesh = ev.to_mesh()
            for i, v in enumerate(mesh.vertices):
                p = m @ v.co
                f.write(f"{frame},{frame / FPS!r},{i},{p.x!r},{p.y!r},{p.z!r}\n")
            ev.to_mesh_clear()


def main():
    out = out_dir()
    os.makedirs(out, exist_ok=True)
    scene, arm, tube = build()
    write_csv(os.path.join(out, "rig_positions.csv"), scene, tube)
    scene.frame_set(0)
    bpy.ops.object.select_all(action="SELECT")
    bpy.ops.export_scene.gltf(filepath=os.path.join(out, "rig.glb"), export_format="GLB",
                              export_animations=True, export_skins=True, export_materials="NONE",
                              export_normals=False, export_texcoords=False)
    bpy.ops.export_scene.fbx(filepath=os.path.join(out, "rig.fbx"), bake_anim=True, add_leaf_bones=False,
                             apply_scale_options="FBX_SCALE_ALL", bake_anim_use_all_actions=False,
                             bake_anim_use_nla_strips=False)
    bpy.ops.wm.collada_export(filepath=os.path.join(out, "rig.dae"), include_animations=True,
                              include_armatures=True, sampling_rate=1, keep_keyframes=False,
                              export_animation_type_selection="sample")
    print("exported rig.glb rig.fbx rig.dae rig_positions.csv into", out)


main()

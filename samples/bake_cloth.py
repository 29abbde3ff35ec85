# Bakes the bundled sample cloth cache with Blender's cloth solver and writes it
# as PC2 point caches with rest-pose OBJ topology (one pair per object) and as
# an OBJ sequence (one OBJ per frame, both objects as `o` groups). Then checks,
# with mathutils.bvhtree, which frames hold real cloth self-intersections and
# cloth-body intersections, and prints the counts per frame.
#
#   blender -b --factory-startup --python samples/bake_cloth.py -- OUTDIR
#
# Scene: a 2 m square cloth (30 x 30 cells, 961 vertices, 1800 triangles,
# self-collision OFF) falls onto a low-poly sphere (radius 0.5 m). Late in the
# animation the sphere rises fast through the draped cloth. Self-collision off
# lets the folds pass through each other; the fast collider tunnels the cloth.
#
# Coordinates are Blender world coordinates (Z up, metres), exactly the float32
# values the PC2 holds; the OBJ files print the same float32 values, widened to
# double, in their shortest exact decimal form (Python's repr), so a parser that
# reads doubles and one that reads floats both get exactly the PC2's values.
import os
import struct
import sys

from array import array

import bpy
from mathutils.bvhtree import BVHTree

FRAME_START = 1
FRAME_END = 40
FPS = 24
CLOTH_CELLS = 30
CLOTH_SIZE = 2.0
CLOTH_HEIGHT = 0.9
SPHERE_RADIUS = 0.5


def out_dir():
    argv = sys.argv
    args = argv[argv.index("--") + 1:] if "--" in argv else []
    if len(args) != 1:
        raise SystemExit("usage: blender -b --factory-startup --python bake_cloth.py -- OUTDIR")
    return args[0]


def clear_scene():
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj, do_unlink=True)


def make_cloth():
    """Grid of triangles, row-major vertices, fixed diagonal: the vertex order
    and triangles are exactly what the files carry."""
    n = CLOTH_CELLS
    verts = []
    for j in range(n + 1):
        for i in range(n + 1):
            x = -CLOTH_SIZE / 2 + CLOTH_SIZE * i / n
            y = -CLOTH_SIZE / 2 + CLOTH_SIZE * j / n
            verts.append((x, y, 0.0))
    faces = []
    for j in range(n):
        for i in range(n):
            v00 = j * (n + 1) + i
            v10 = v00 + 1
            v01 = v00 + (n + 1)
            v11 = v01 + 1
            faces.append((v00, v10, v11))
            faces.append((v00, v11, v01))
    mesh = bpy.data.meshes.new("cloth")
    mesh.from_pydata(verts, [], faces)
    mesh.update()
    obj = bpy.data.objects.new("cloth", mesh)
    bpy.context.scene.collection.objects.link(obj)
    # Slightly tilted so the fall is not perfectly symmetric and folds form.
    obj.location = (0.12, -0.07, CLOTH_HEIGHT)
    obj.rotation_euler = (0.05, -0.08, 0.3)
    cloth = obj.modifiers.new("Cloth", "CLOTH")
    cloth.settings.quality = 5
    cloth.settings.mass = 0.3
    cloth.settings.tension_stiffness = 15
    cloth.settings.compression_stiffness = 15
    cloth.settings.bending_stiffness = 0.05
    cloth.collision_settings.use_collision = True
    cloth.collision_settings.use_self_collision = False
    cloth.collision_settings.distance_min = 0.005
    cloth.collision_settings.collision_quality = 2
    cloth.point_cache.frame_start = FRAME_START
    cloth.point_cache.frame_end = FRAME_END
    return obj


def make_body():
    bpy.ops.mesh.primitive_uv_sphere_add(segments=16, ring_count=8, radius=SPHERE_RADIUS,
                                         location=(0.0, 0.0, 0.0))
    obj = bpy.context.active_object
    obj.name = "body"
    obj.data.name = "body"
    # Triangulate in the mesh itself so the topology is explicit.
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.mesh.select_all(action="SELECT")
    bpy.ops.mesh.quads_convert_to_tris(quad_method="FIXED", ngon_method="BEAUTY")
    bpy.ops.object.mode_set(mode="OBJECT")
    col = obj.modifiers.new("Collision", "COLLISION")
    col.settings.thickness_outer = 0.005
    col.settings.cloth_friction = 5.0
    # Rests, then rises fast through the draped cloth.
    for frame, z in ((1, 0.0), (26, 0.0), (33, 1.4), (40, 1.6)):
        obj.location = (0.0, 0.0, z)
        obj.keyframe_insert("location", frame=frame)
    for fc in obj.animation_data.action.fcurves:
        for key in fc.keyframe_points:
            key.interpolation = "LINEAR"
    return obj


def triangles_of(obj):
    tris = [tuple(p.vertices) for p in obj.data.polygons]
    for t in tris:
        if len(t) != 3:
            raise SystemExit(f"{obj.name}: polygon with {len(t)} vertices")
    return tris


def world_positions(obj, depsgraph):
    """Evaluated world positions rounded to float32: a list of (x, y, z)."""
    ev = obj.evaluated_get(depsgraph)
    mesh = ev.to_mesh()
    m = ev.matrix_world.copy()
    world = array("f")
    for v in mesh.vertices:
        world.extend(m @ v.co)
    ev.to_mesh_clear()
    return [tuple(world[3 * i:3 * i + 3]) for i in range(len(world) // 3)]


def write_pc2(path, frames):
    """PC2: 'POINTCACHE2\\0', int32 version 1, int32 points, float32 start
    frame, float32 sample rate, int32 samples, then float32 xyz per point."""
    with open(path, "wb") as f:
        f.write(b"POINTCACHE2\0")
        f.write(struct.pack("<iiffi", 1, len(frames[0]), float(FRAME_START), 1.0, len(frames)))
        for p in frames:
            f.write(struct.pack(f"<{3 * len(p)}f", *[c for xyz in p for c in xyz]))


def obj_lines(name, positions, tris, vertex_base):
    lines = [f"o {name}\n"]
    for x, y, z in positions:
        lines.append(f"v {x!r} {y!r} {z!r}\n")
    for a, b, c in tris:
        lines.append(f"f {a + 1 + vertex_base} {b + 1 + vertex_base} {c + 1 + vertex_base}\n")
    return lines


def count_intersections(cloth_pos, cloth_tris, body_pos, body_tris):
    cloth_tree = BVHTree.FromPolygons(cloth_pos, cloth_tris, all_triangles=True)
    body_tree = BVHTree.FromPolygons(body_pos, body_tris, all_triangles=True)
    self_pairs = 0
    for a, b in cloth_tree.overlap(cloth_tree):
        if a < b and not set(cloth_tris[a]) & set(cloth_tris[b]):
            self_pairs += 1
    body_pairs = len(cloth_tree.overlap(body_tree))
    return self_pairs, body_pairs


def main():
    out = out_dir()
    os.makedirs(os.path.join(out, "obj_sequence"), exist_ok=True)
    clear_scene()
    scene = bpy.context.scene
    scene.render.fps = FPS
    scene.frame_start = FRAME_START
    scene.frame_end = FRAME_END
    body = make_body()
    cloth = make_cloth()
    objects = [cloth, body]
    topo = {o.name: triangles_of(o) for o in objects}

    frames = {o.name: [] for o in objects}
    for frame in range(FRAME_START, FRAME_END + 1):
        scene.frame_set(frame)
        depsgraph = bpy.context.evaluated_depsgraph_get()
        for o in objects:
            frames[o.name].append(world_positions(o, depsgraph))

    for o in objects:
        write_pc2(os.path.join(out, f"{o.name}.pc2"), frames[o.name])
        with open(os.path.join(out, f"{o.name}_rest.obj"), "w") as f:
            f.write(f"# {o.name}: rest pose (frame {FRAME_START}) of {o.name}.pc2, same vertex order\n")
            f.writelines(obj_lines(o.name, frames[o.name][0], topo[o.name], 0))

    print("frame self_pairs cloth_body_pairs")
    for k, frame in enumerate(range(FRAME_START, FRAME_END + 1)):
        path = os.path.join(out, "obj_sequence", f"cloth_ball_{frame:04d}.obj")
        with open(path, "w") as f:
            f.write(f"# frame {frame} of cloth.pc2 and body.pc2\n")
            base = 0
            for o in objects:
                f.writelines(obj_lines(o.name, frames[o.name][k], topo[o.name], base))
                base += len(frames[o.name][k])
        s, b = count_intersections(frames["cloth"][k], topo["cloth"], frames["body"][k], topo["body"])
        print(f"{frame} {s} {b}")
    for o in objects:
        print(f"object {o.name}: {len(frames[o.name][0])} vertices, {len(topo[o.name])} triangles")


main()

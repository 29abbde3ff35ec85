# Bakes a large cloth cache with Blender's cloth solver, for benchmarks of
# static detection and CCD at 10k and 100k faces (snag-bench-pipeline --cache).
# The bundled sample (samples/bake_cloth.py) is small and written vertex by
# vertex in Python; this script writes with foreach_get and numpy so that a
# 100k-face frame takes milliseconds, and it bakes only the frames asked for.
#
#   blender -b --factory-startup --python scripts/bake_cloth_cache.py -- \
#       OUTDIR --cells N [--frames F] [--subdivide L] [--body sphere|funnel]
#       [--self-collision] [--keep-from K]
#
# Scene: a 2 m square cloth of N x N cells (2·N² triangles, self-collision
# OFF, so folds pass through each other) falls onto a UV sphere (r = 0.5 m,
# 32 segments, 16 rings, at rest).
#
# --body funnel puts an open funnel at rest under the cloth instead (a cone
# without caps, 48 sides, rim radius 0.7 m at z = 0.35, neck radius 0.05 m at
# z = -0.45), and --self-collision turns the cloth's self-collision on: the
# cloth sags into the funnel and jams in its neck, layer on layer (96 cells:
# from about frame 33 half of it hangs below the neck, sliding slowly), its
# folds held about the solver's collision distance (5 mm) apart: a long
# stretch of tight contact, made by a solver nobody here wrote. It is not the
# published "cloth-funnel" CCD scene, whose gaps (IPC's, 1e-3 and less) leave
# many queries undecided: at 5 mm the early exits decide them all.
# --keep-from K writes only frames K to F (the PC2's start frame is K, the
# rest OBJ frame K), so that a long bake keeps only its contact-rich end.
#
# --subdivide L applies Blender's "simple"
# subdivision L times after the cloth solver and triangulates: each triangle
# becomes 6 lying in its plane, so the intersections of the simulated cloth
# are kept and the face count grows sixfold per level without simulating the
# finer mesh (N = 92, L = 1: 101,568 cloth triangles).
#
# Output in OUTDIR: cloth.pc2 + cloth_rest.obj and body.pc2 + body_rest.obj
# (PC2 version 1, start frame 1 or K, float32 world positions; the OBJ is the
# first frame written, with the same vertex order). Load with snag-scan or
# snag-bench-pipeline as two inputs, each PC2 with its OBJ as topology.
import argparse
import os
import sys

import bpy
import numpy as np

FRAME_START = 1
CLOTH_SIZE = 2.0
CLOTH_HEIGHT = 0.9
SPHERE_RADIUS = 0.5
FUNNEL_SIDES = 48
FUNNEL_RIM_RADIUS, FUNNEL_RIM_Z = 0.7, 0.35
FUNNEL_NECK_RADIUS, FUNNEL_NECK_Z = 0.05, -0.45


def arguments():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    parser = argparse.ArgumentParser(prog="bake_cloth_cache.py")
    parser.add_argument("out_dir")
    parser.add_argument("--cells", type=int, required=True, help="cloth cells per side (2·N² triangles)")
    parser.add_argument("--frames", type=int, default=40, help="frames to bake (from frame 1)")
    parser.add_argument("--subdivide", type=int, default=0, help="simple subdivision levels after the solver")
    parser.add_argument("--body", choices=("sphere", "funnel"), default="sphere", help="the collider under the cloth")
    parser.add_argument("--self-collision", action="store_true", help="the cloth's self-collision on")
    parser.add_argument("--keep-from", type=int, default=FRAME_START, help="the first frame written")
    args = parser.parse_args(argv)
    if not FRAME_START <= args.keep_from < FRAME_START + args.frames:
        parser.error("--keep-from must be one of the baked frames")
    return args


def make_cloth(cells, frame_end, subdivide, self_collision):
    n = cells
    ij = np.stack(np.meshgrid(np.arange(n + 1), np.arange(n + 1)), -1).reshape(-1, 2)
    verts = np.zeros((len(ij), 3))
    verts[:, :2] = -CLOTH_SIZE / 2 + CLOTH_SIZE * ij / n
    v00 = (np.arange(n)[None, :] + (n + 1) * np.arange(n)[:, None]).ravel()
    faces = np.concatenate([np.stack([v00, v00 + 1, v00 + n + 2], 1), np.stack([v00, v00 + n + 2, v00 + n + 1], 1)])
    mesh = bpy.data.meshes.new("cloth")
    mesh.from_pydata(verts.tolist(), [], faces.tolist())
    mesh.update()
    obj = bpy.data.objects.new("cloth", mesh)
    bpy.context.scene.collection.objects.link(obj)
    # Tilted so the fall is not symmetric and folds form.
    obj.location = (0.12, -0.07, CLOTH_HEIGHT)
    obj.rotation_euler = (0.05, -0.08, 0.3)
    cloth = obj.modifiers.new("Cloth", "CLOTH")
    cloth.settings.quality = 5
    cloth.settings.mass = 0.3
    cloth.settings.tension_stiffness = 15
    cloth.settings.compression_stiffness = 15
    cloth.settings.bending_stiffness = 0.05
    cloth.collision_settings.use_collision = True
    cloth.collision_settings.use_self_collision = self_collision
    cloth.collision_settings.self_distance_min = 0.005
    cloth.collision_settings.distance_min = 0.005
    cloth.collision_settings.collision_quality = 2
    cloth.point_cache.frame_start = FRAME_START
    cloth.point_cache.frame_end = frame_end
    if subdivide > 0:
        sub = obj.modifiers.new("Subdivision", "SUBSURF")
        sub.subdivision_type = "SIMPLE"
        sub.levels = sub.render_levels = subdivide
        tri = obj.modifiers.new("Triangulate", "TRIANGULATE")
        tri.quad_method = "FIXED"
    return obj


def make_body(shape):
    if shape == "funnel":
        bpy.ops.mesh.primitive_cone_add(vertices=FUNNEL_SIDES, radius1=FUNNEL_NECK_RADIUS, radius2=FUNNEL_RIM_RADIUS,
                                        depth=FUNNEL_RIM_Z - FUNNEL_NECK_Z, end_fill_type="NOTHING",
                                        location=(0, 0, (FUNNEL_RIM_Z + FUNNEL_NECK_Z) / 2))
    else:
        bpy.ops.mesh.primitive_uv_sphere_add(segments=32, ring_count=16, radius=SPHERE_RADIUS, location=(0, 0, 0))
    obj = bpy.context.active_object
    obj.name = obj.data.name = "body"
    obj.modifiers.new("Triangulate", "TRIANGULATE").quad_method = "FIXED"
    collision = obj.modifiers.new("Collision", "COLLISION").settings
    collision.thickness_outer = 0.005
    # The cloth falls into the funnel, on the side its normals face away from:
    # both sides collide.
    collision.use_culling = False
    return obj


def evaluated(obj, depsgraph):
    """World positions (#V by 3, float32) and triangles (#F by 3) of the evaluated mesh."""
    ev = obj.evaluated_get(depsgraph)
    mesh = ev.to_mesh()
    co = np.empty(3 * len(mesh.vertices), np.float32)
    mesh.vertices.foreach_get("co", co)
    loops = np.empty(len(mesh.polygons), np.int32)
    mesh.polygons.foreach_get("loop_total", loops)
    if np.any(loops != 3):
        raise SystemExit(f"{obj.name}: a polygon that is not a triangle")
    tris = np.empty(3 * len(mesh.polygons), np.int32)
    mesh.polygons.foreach_get("vertices", tris)
    m = np.array(ev.matrix_world, np.float64)
    ev.to_mesh_clear()
    world = co.reshape(-1, 3).astype(np.float64) @ m[:3, :3].T + m[:3, 3]
    return world.astype(np.float32), tris.reshape(-1, 3)


def write_pc2(path, frames, start):
    with open(path, "wb") as f:
        f.write(b"POINTCACHE2\0")
        f.write(np.array([1, len(frames[0])], "<i4").tobytes())
        f.write(np.array([start, 1.0], "<f4").tobytes())
        f.write(np.array([len(frames)], "<i4").tobytes())
        for p in frames:
            f.write(p.astype("<f4").tobytes())


def write_rest_obj(path, name, positions, tris, frame):
    with open(path, "w") as f:
        f.write(f"# {name}: rest pose (frame {frame}) of {name}.pc2, same vertex order\no {name}\n")
        # repr of the float32 widened to double: read back bit for bit.
        f.writelines(f"v {x!r} {y!r} {z!r}\n" for x, y, z in positions.astype(np.float64).tolist())
        f.writelines(f"f {a} {b} {c}\n" for a, b, c in (tris + 1).tolist())


def main():
    args = arguments()
    os.makedirs(args.out_dir, exist_ok=True)
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj, do_unlink=True)
    scene = bpy.context.scene
    scene.frame_start, scene.frame_end = FRAME_START, FRAME_START + args.frames - 1
    objects = [make_cloth(args.cells, scene.frame_end, args.subdivide, args.self_collision), make_body(args.body)]
    frames = {o.name: [] for o in objects}
    topology = {}
    for frame in range(scene.frame_start, scene.frame_end + 1):
        scene.frame_set(frame)
        depsgraph = bpy.context.evaluated_depsgraph_get()
        for o in objects:
            positions, tris = evaluated(o, depsgraph)
            if topology.setdefault(o.name, tris) is not tris and not np.array_equal(topology[o.name], tris):
                raise SystemExit(f"{o.name}: topology changed at frame {frame}")
            if frame >= args.keep_from:
                frames[o.name].append(positions)
        print(f"frame {frame} baked", flush=True)
    for o in objects:
        write_pc2(os.path.join(args.out_dir, f"{o.name}.pc2"), frames[o.name], args.keep_from)
        write_rest_obj(os.path.join(args.out_dir, f"{o.name}_rest.obj"), o.name, frames[o.name][0], topology[o.name],
                       args.keep_from)
        print(f"object {o.name}: {len(frames[o.name][0])} vertices, {len(topology[o.name])} triangles")


main()

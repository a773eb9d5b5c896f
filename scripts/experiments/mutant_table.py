"""The mutation suite's mutants (scripts/experiments/mutants.py builds and runs each): a one-place change to the
shadow pipeline each, as (name, file, how the file's text changes, what the change does[, what it adds to MATRIX]).
A mutant names text that occurs exactly as often as it expects (tests/mutants_apply_test.py holds every one to this
tree), and docs/mutants.md records each one's name and what caught it.
"""
import re

# The matrix each mutant runs: the default scenes and spot (its 2D map) and filters, every technique a backend can do, smaller frames
# and cubes than the default run (a planted bug fails at any size; that correct code passes at the large ones is
# scripts/ci/large_cube_checks.sh's), untimed: a mutant is caught by its checks, never by a time.
MATRIX = ["--scene", "room,heavy,spot", "--cube", "256", "--frame", "400x300", "--no-timing", "--images", "none",
          "--check"]
FACES = ["+X", "-X", "+Y", "-Y", "+Z", "-Z"]
# What the moments filters' mutants add to MATRIX: the default filters and every moments filter, as the binary
# under test lists them (`omnishadow list`: "moments filters: ..."), put in for MOMENTS when the matrix runs.
MOMENTS = "MOMENTS"
MOMENTS_FILTERS = ["--filter", "hard,pcf_grid64,pcf_disk20," + MOMENTS]
# What the layout mutants add: the face_array layout, every default filter and a moments one (bilinear per face).
FACE_ARRAY = ["--layout", "face_array", "--filter", "hard,pcf_grid64,pcf_disk20,vsm"]
# dual_paraboloid, tessellated so that its own error is small next to a planted bug's.
PARABOLOID = ["--layout", "dual_paraboloid", "--tessellate", "8", "--filter", "hard,pcf_disk20"]
TETRA = ["--layout", "tetrahedral", "--filter", "hard,pcf_disk20"]
# A light whose range ends inside its room (the hall's first lamp): its own scene replaces the default ones.
RANGE = ["--scene", "hall", "--light-count", "1", "--filter", "hard,pcf_disk20"]
# Four of the hall's lamps, each in its own layers of one texture (light k's cube k of a cube-map array, or its six
# layers of a 2D array): every one of them is checked against its own truth.
MANY = ["--scene", "hall", "--light-count", "4", "--layout", "cube_array,face_array", "--filter", "hard,pcf_disk20"]
# The same lamps as tiles of one atlas, per face and in one pass routed by viewport.
ATLAS = ["--scene", "hall", "--light-count", "4", "--layout", "atlas", "--technique", "six_pass,geometry_shader",
         "--filter", "hard,pcf_disk20"]
# The same lamps with every light in one pass (vs_layer), beside six_pass per light.
ONE_PASS = MANY + ["--technique", "six_pass,vs_layer", "--light-grouping", "per_light,all_lights"]
# The same with the geometry shader's one pass (invocations per light).
GS_ONE_PASS = MANY + ["--technique", "six_pass,geometry_shader", "--light-grouping", "per_light,all_lights"]
# Sixteen lamps seen from mid-hall, culled to the view (lamps behind the camera get no pass, faces turned away
# none): every case is held to six_pass unculled, and its covered pixels to the faces it drew.
VIEW = ["--scene", "hall", "--light-count", "16", "--camera", "0,3,0,20,2,0", "--optimize", "view",
        "--technique", "six_pass,geometry_shader", "--filter", "hard,pcf_disk20"]
# The same lamps with the camera walking 16 units back down the hall (--camera's sway), checked where the walk
# ends (frame 188): the lamps it passes come into view, and the maps and lists must follow it.
WALK = ["--scene", "hall", "--light-count", "16", "--camera", "0,3,0,20,2,0,-16,0,0", "--check-frame", "188",
        "--optimize", "view+clusters", "--technique", "six_pass", "--filter", "hard,pcf_disk20"]
# The walk alone, nothing culled or listed: the frame's own matrices must follow the camera.
WALK_PLAIN = ["--scene", "hall", "--light-count", "16", "--camera", "0,3,0,20,2,0,-16,0,0", "--check-frame", "188",
              "--technique", "six_pass,geometry_shader", "--filter", "hard"]
# Sixteen lamps shaded from clustered light lists: every case is held to the loop over every light, and every
# covered pixel's cluster to the lights that reach it.
CLUSTERS = ["--scene", "hall", "--light-count", "16", "--optimize", "clusters", "--technique", "six_pass",
            "--filter", "hard,pcf_disk20"]
# Sixteen lamps in an atlas whose tiles follow each lamp's screen coverage within 256K texels.
BUDGET = ["--scene", "hall", "--light-count", "16", "--layout", "atlas", "--atlas-tiles", "by_coverage",
          "--shadow-budget", "256K", "--technique", "six_pass", "--filter", "hard,pcf_disk20"]
# Twenty-four lamps in an atlas whose tiles are planned again every frame by distance, without and with an update
# budget of four lamps a frame, the camera walking 16 units back down the hall, checked where the walk ends and over
# a staleness sequence of its first 24 frames (re-plans at frames 14, 17 and 21 move blocks): a moved lamp must render
# again where the records now point. (Not with the static cache: the hall's rollers and carts reach every lamp, so
# no lamp keeps its map there anyway.)
REPLAN = ["--scene", "hall", "--light-count", "24", "--camera", "0,3,0,20,2,0,-16,0,0", "--check-frame", "188",
          "--layout", "atlas", "--atlas-tiles", "by_distance", "--atlas-replan", "1", "--update-budget", "none,24",
          "--staleness-frames", "24", "--technique", "six_pass", "--filter", "hard"]
# Sixteen lamps (four swaying) under an update budget of 8 faces a frame, faces one by one (six_pass) and whole
# lights (geometry_shader), with the staleness sequence that holds what every face shows to the lamps' paths.
UPDATE = ["--scene", "hall", "--light-count", "16", "--update-budget", "8", "--technique", "six_pass,geometry_shader",
          "--filter", "hard"]
# Four of the hall's lamps at a frame far from the one the scene loads at, its rollers and carts moved there, with
# and without the static cache (whose cold frame is then the next one: the check frame keeps what the dirty rule
# lets it keep of a frame whose casters stood elsewhere).
MOVING = ["--scene", "hall", "--light-count", "4", "--check-frame", "90", "--optimize", "none,cache",
          "--technique", "six_pass,geometry_shader", "--filter", "hard"]
# Four of the hall's lamps, each its own cube and sampler (layout cube with several lights).
CUBES = ["--scene", "hall", "--light-count", "4", "--layout", "cube", "--filter", "hard,pcf_disk20"]
# nv_swizzle with r32f_distance (its reversed depth, no far plane) where four of the hall's lamps' ranges end inside
# the hall, in a cube array and in an atlas (faces routed by viewport).
SWIZZLE_RANGE = ["--scene", "hall", "--light-count", "4", "--layout", "cube_array,atlas", "--technique",
                 "six_pass,nv_swizzle", "--emulate-nv-swizzle", "--storage", "r32f_distance", "--filter", "hard"]
# mesh_shader through its test-only emulation (Mesa lacks mesh shading) on four of the hall's lamps at a frame where
# the casters have moved: per light, culled, and every light in one pass.
MESH = ["--scene", "hall", "--light-count", "4", "--check-frame", "12", "--layout", "cube_array", "--technique",
        "six_pass,mesh_shader", "--emulate-mesh-shader", "--light-grouping", "per_light,all_lights",
        "--optimize", "none,cull", "--filter", "hard"]
# nv_swizzle through its test-only emulation (an ordinary GS applies the swizzles): Mesa lacks the NV extensions.
SWIZZLE = ["--technique", "six_pass,nv_swizzle", "--emulate-nv-swizzle", "--storage", "linear_depth,r32f_distance",
           "--optimize", "none,cull", "--filter", "hard"]



def flip_up(face):
    """kFaceUps[face] negated (backends/common/cube_faces.h)."""
    def apply(text):
        block = re.search(r"kFaceUps = \{(.*?)\};", text, re.S)
        vecs = re.findall(r"glm::vec3\(([^)]*)\)", block.group(1))
        parts = [int(v) for v in vecs[face].split(",")]
        vecs[face] = ", ".join(str(-p) if p else "0" for p in parts)
        rows = [", ".join(f"glm::vec3({v})" for v in vecs[i:i + 3]) for i in (0, 3)]
        return text[:block.start(1)] + "\n    " + ",\n    ".join(rows) + text[block.end(1):]
    return apply


def replace(old, new, count=1):
    def apply(text):
        found = text.count(old)
        if found != count:
            raise ValueError(f"expected {count} occurrence(s) of {old!r}, found {found}")
        return text.replace(old, new)
    return apply


MUTANTS = [(f"up_flip_{FACES[f]}", "backends/common/cube_faces.h", flip_up(f),
            f"the {FACES[f]} face's up vector negated") for f in range(6)] + [
    ("faces_swapped", "backends/common/cube_faces.h",
     replace("glm::vec3(1, 0, 0), glm::vec3(-1, 0, 0),", "glm::vec3(-1, 0, 0), glm::vec3(1, 0, 0),"),
     "the +X and -X faces' directions swapped"),
    ("fov_91", "backends/common/cube_faces.cpp", replace("glm::radians(90.0f)", "glm::radians(91.0f)", 2),
     "the face projection's field of view 91 degrees instead of 90"),
    ("bias_dropped", "shaders/shadow_filters.glsl", replace("  return tutorial_bias;", "  return 0.0;"),
     "the lookups' constant bias dropped (0 instead of 0.05 / 0.15)"),
    ("no_divide_by_far", "shaders/shadow_depth.frag",
     replace("length(world_position - light_position()) / light_far();  // the point-shadow tutorial",
             "length(world_position - light_position());  // the point-shadow tutorial"),
     "linear depth stored without the divide by far"),
    ("lookup_x_flipped", "shaders/shadow_filters.glsl",
     replace("bias > stored_to_distance(texture(shadow_map, shadow_coord(dir)).r",
             "bias > stored_to_distance(texture(shadow_map, shadow_coord(dir * vec3(-1.0, 1.0, 1.0))).r"),
     "the lookup direction's x negated"),
    ("pcf_grid_x10", "shaders/shadow_filters.glsl",
     replace("float grid_offset = 0.1 * frame.knobs.y;", "float grid_offset = 1.0 * frame.knobs.y;"),
     "the grid PCF's offsets scaled by 10"),
    ("pcf_disk_x10", "shaders/shadow_filters.glsl",
     replace("/ 25.0 * frame.knobs.y;", "/ 2.5 * frame.knobs.y;"),
     "the disk PCF's radius scaled by 10"),
    ("far_mismatch_1pct", "shaders/shadow_depth.frag",
     replace("/ light_far();  // the point-shadow tutorial", "/ (light_far() * 1.01);  // the point-shadow tutorial"),
     "the shadow pass divides by a far plane 1% larger than the lighting pass multiplies by"),
    ("lookup_half_texel", "shaders/shadow_filters.glsl",
     replace("bias > stored_to_distance(texture(shadow_map, shadow_coord(dir)).r",
             "bias > stored_to_distance(texture(shadow_map, shadow_coord(dir + vec3(0.0, max(max(abs(dir.x), abs(dir.y)), "
             "abs(dir.z)) / float(textureSize(shadow_map, 0).x), 0.0))).r"),
     "the hard lookup's direction moved by half a texel along y (faces other than +-Y)"),
    ("spot_view_transposed", "backends/common/map_lights.cpp",
     replace("glm::mat4 view = glm::lookAtRH(position, position + light.direction, map_up(light.direction));",
             "glm::mat4 view = glm::transpose(glm::lookAtRH(position, position + light.direction, "
             "map_up(light.direction)));"),
     "the spot light map's view matrix transposed"),
    ("gs_wrong_layer", "shaders/shadow_depth.geom",
     replace("gl_Layer = face;  // per vertex", "gl_Layer = face == 4 ? 5 : face;  // per vertex"),
     "the geometry-shader techniques write the +Z face into the -Z layer"),
    # The moments filters: their matrix adds the filter (MOMENTS_FILTERS), so the unmutated run does too.
    ("vsm_not_squared", "shaders/moments.glsl",
     replace("return vec4(d, d * d, 0.0, 0.0);", "return vec4(d, d, 0.0, 0.0);"),
     "VSM's second moment stored as z instead of z^2", MOMENTS_FILTERS),
    ("esm_exponent_sign", "shaders/moments.glsl",
     replace("return vec4(exp(frame.knobs.w * min(z, 1.0)), 0.0, 0.0, 0.0);",
             "return vec4(exp(-frame.knobs.w * min(z, 1.0)), 0.0, 0.0, 0.0);"),
     "ESM's stored exponential with the exponent's sign flipped", MOMENTS_FILTERS),
    ("evsm_negative_warp_unsigned", "shaders/moments.glsl",
     replace("return vec4(p, p * p, -n, n * n);", "return vec4(p, p * p, n, n * n);"),
     "EVSM4's negative warp stored as +e^(-cz) instead of -e^(-cz)", MOMENTS_FILTERS),
    ("msm_fourth_moment_cubed", "shaders/moments.glsl",
     replace("return vec4(c, c2, c2 * c, c2 * c2);", "return vec4(c, c2, c2 * c, c2 * c);"),
     "MSM's fourth moment stored as z^3", MOMENTS_FILTERS),
    ("blur_skips_face", "shaders/moments_blur.comp",
     replace("  vec4 sum = vec4(0.0);", "  if (id.z == 5) { imageStore(target, id, imageLoad(source, id)); return; }\n"
             "  vec4 sum = vec4(0.0);"),
     "the moments blur copies the -Z face instead of blurring it", MOMENTS_FILTERS),
    ("blur_tap_shifted", "shaders/moments_blur.comp",
     replace("neighbour_texel(id.z, id.x, id.y, axis, k, size)", "neighbour_texel(id.z, id.x, id.y, axis, k + 1, size)"),
     "the moments blur's taps shifted by one texel (the kernel off centre)", MOMENTS_FILTERS),
    ("blur_seam_clamped", "shaders/cube_texel.glsl",
     replace("  ivec3 p = texel_point(face, s, t, size);",
             "  return ivec3(clamp(s, 0, size - 1), clamp(t, 0, size - 1), face);\n  ivec3 p = texel_point(face, s, t, size);"),
     "the moments blur clamps at a face's edge instead of reading the adjacent face", MOMENTS_FILTERS),
    # Layouts: the face_array lookup picks the layer and (s, t) in the shader; its matrix names the layout.
    ("face_array_y_layers_swapped", "shaders/shadow_filters.glsl",
     replace("face = dir.y >= 0.0 ? 2.0 : 3.0;", "face = dir.y >= 0.0 ? 3.0 : 2.0;"),
     "the face_array lookup reads the -Y layer for +Y directions and the +Y layer for -Y", FACE_ARRAY),
    ("face_array_t_flipped_on_z", "shaders/shadow_filters.glsl",
     replace("    sc = dir.z >= 0.0 ? dir.x : -dir.x;\n    tc = -dir.y;", "    sc = dir.z >= 0.0 ? dir.x : -dir.x;\n    tc = dir.y;"),
     "the face_array lookup's t flipped on the +-Z faces", FACE_ARRAY),
    # dual_paraboloid: the warp (shadow pass) and the lookup (lighting) are separate GLSL; both must follow
    # backends/common/paraboloid.h. Its texels are a figure, not a check, so exact visibility must catch these.
    ("paraboloid_lookup_layers_swapped", "shaders/paraboloid.glsl",
     replace("float layer = dir.z >= 0.0 ? 0.0 : 1.0;", "float layer = dir.z >= 0.0 ? 1.0 : 0.0;"),
     "the paraboloid lookup reads the -Z layer for +Z directions and the +Z layer for -Z", PARABOLOID),
    ("paraboloid_warp_x_unmirrored", "shaders/paraboloid.glsl",
     replace("float vx = layer == 0 ? -v.x : v.x;", "float vx = v.x;"),
     "the shadow pass's warp does not mirror x in layer 0 (seen along +Z), so that layer is stored mirrored", PARABOLOID),
    # tetrahedral: the GLSL lookup states each face's camera in closed form, by the same rule as
    # backends/common/tetrahedron.h; this mutant's bases are the rule's with the corner of face + 2, not face + 1.
    ("tetra_lookup_up_to_wrong_corner", "shaders/shadow_filters.glsl",
     replace("kTetraUps[4] = vec3[](vec3(-2, 1, 1), vec3(1, -1, 2), vec3(2, 1, -1), vec3(-1, -1, -2));\n"
             "const vec3 kTetraRights[4] = vec3[](vec3(0, -1, 1), vec3(-1, -1, 0), vec3(0, -1, -1), vec3(1, -1, 0));",
             "kTetraUps[4] = vec3[](vec3(1, -2, 1), vec3(1, 2, -1), vec3(-1, -2, -1), vec3(-1, 2, 1));\n"
             "const vec3 kTetraRights[4] = vec3[](vec3(1, 0, -1), vec3(1, 0, 1), vec3(-1, 0, 1), vec3(-1, 0, -1));"),
     "the tetrahedral lookup turns each face's up towards another corner than the shadow pass's camera", TETRA),
    # nv_swizzle: the swizzle table, the GS's culling, the reversed depth of r32f_distance.
    ("swizzle_y_negated", "backends/common/viewport_swizzle.cpp",
     replace("axis_of_row(view, 1, 1.0f, f)", "axis_of_row(view, 1, -1.0f, f)"),
     "every face's swizzle negates clip y (each face stored upside down)", SWIZZLE),
    ("swizzle_cull_axis_sign_flipped", "shaders/shadow_swizzle.geom",
     replace("const float s = (f & 1) == 0 ? 1.0 : -1.0;", "const float s = (f & 1) == 0 ? -1.0 : 1.0;"),
     "nv_swizzle's culling tests each face against the opposite face's axis", SWIZZLE),
    ("swizzle_depth_not_reversed", "backends/common/techniques.cpp",
     replace("return c.technique == Technique::nv_swizzle && !traits(c.storage).fragment_depth;", "return false;"),
     "nv_swizzle's r32f_distance keeps fragments by LESS against 1: its reversed depth keeps the farthest", SWIZZLE),
    ("light_cubes_shifted", "shaders/shadow_filters.glsl",
     replace("#define shadow_map shadow_cubes[g_light]", "#define shadow_map shadow_cubes[(g_light + 1) % 4]"),
     "layout cube with several lights: light k's lookups read light k + 1's cube (its own sampler's neighbour)", CUBES),
    ("swizzle_far_kept", "shaders/shadow_depth.frag",
     replace("  if (gl_FragCoord.w * light_far() < 1.0) discard;", ""),
     "nv_swizzle's r32f_distance stores what lies past far (its depth has no far plane)", SWIZZLE_RANGE),
    ("swizzle_atlas_by_layer", "shaders/shadow_swizzle.geom",
     replace("      gl_ViewportIndex = f;  // face f's tile", "      gl_Layer = f;  // face f's tile"),
     "nv_swizzle's (emulated) copies go to layer f of an atlas that has one, not to face f's tile", SWIZZLE_RANGE),
    ("range_ignored", "shaders/lighting.frag",
     replace("float light_shadow = in_range ? looked_up : 0.0;", "float light_shadow = looked_up;"),
     "a point light's range ignored: beyond its far the shadow factor is what the filter reads there", RANGE),
    ("light_maps_swapped", "shaders/shadow_filters.glsl",
     replace("shadow_face_size()), float(g_light)); }", "shadow_face_size()), float(g_light ^ 1)); }"),
     "the lighting pass reads light 1's cube for light 0 and light 0's for light 1 (likewise 2 and 3)", MANY),
    ("light_far_from_first", "shaders/common.glsl",
     replace("float light_far() { return point_lights[g_light].position_far.w; }",
             "float light_far() { return point_lights[0].position_far.w; }"),
     "every light's lookups and range take the first light's far (the hall's swaying lamps reach less far)", MANY),
    ("one_pass_layers_of_first_light", "shaders/shadow_depth.vert",
     replace("  gl_Layer = instance;\n", "  gl_Layer = face;\n"),
     "every light in one pass renders each light's faces into the first light's layers", ONE_PASS),
    ("gs_one_pass_layers_of_first_light", "shaders/shadow_depth.geom",
     replace("    gl_Layer = 6 * light + face;", "    gl_Layer = face;"),
     "the geometry shader's one pass renders each light's faces into the first light's layers", GS_ONE_PASS),
    ("atlas_tile_off_by_one", "backends/common/atlas.cpp",
     replace("(face / 3) * span + kBorder};", "(face / 3) * span + kBorder + 1};"),
     "every atlas tile rendered and read back one texel up from where the lighting pass looks it up", ATLAS),
    ("view_culls_light_by_centre", "backends/common/view_culling.cpp",
     replace("if (planes[i].distance(light) > range + margin)", "if (planes[i].distance(light) > margin)"),
     "view culling tests the light's position against the frustum, not its range sphere: lamps beside the view "
     "whose range reaches into it get no map", VIEW),
    ("cluster_lists_drop_last_light", "backends/common/light_clusters.cpp",
     replace("for (uint32_t k = 0; k < lights.size(); ++k) {", "for (uint32_t k = 0; k + 1 < lights.size(); ++k) {"),
     "the clustered light lists leave out the case's last light: no pixel is shaded by it", CLUSTERS),
    ("view_culls_to_camera_at_rest", "backends/common/view_culling.cpp",
     replace("  const scene::Camera camera = scene.camera.at(frame);", "  const scene::Camera camera = scene.camera;"),
     "view culling culls to the camera where the scene put it, not where the frame has it: the lamps a walking "
     "camera passes get no map", WALK),
    ("cluster_lists_for_camera_at_rest", "backends/common/light_clusters.cpp",
     replace("  grid_.view = cube::camera_view(camera, grid_.width, grid_.height);", "  (void)camera;"),
     "the clustered lists are built over the frustum of the camera where the scene put it: a walking camera's "
     "pixels are shaded from another place's lists", WALK),
    ("frame_camera_at_rest", "backends/common/frame_uniforms.cpp",
     replace("  const scene::Camera cam = scene.camera.at(frame);", "  const scene::Camera cam = scene.camera;"),
     "the frame's matrices see through the camera where the scene put it, not where the frame has it on its walk",
     WALK_PLAIN),
    ("budget_allocation_exceeds_budget", "backends/common/atlas.cpp",
     replace("return uint64_t(plan.width) * uint64_t(plan.height) <= budget;",
             "return uint64_t(plan.width) * uint64_t(plan.height) <= 2 * budget;"),
     "the coverage allocation accepts an atlas of up to twice its --shadow-budget", BUDGET),
    ("replan_keeps_moved_maps", "backends/common/shadow_frame.cpp",
     replace("    planners_[k].reset();\n    ++f.atlas_relocated;", "    ++f.atlas_relocated;"),
     "an atlas re-plan moves a lamp's block but the planner keeps its map: the lamp renders again only when the update "
     "budget gets to it, its texels left where its block was", REPLAN),
    ("replan_never_reaches_the_passes", "backends/common/shadow_frame.cpp",
     replace("  f.atlas_replanned = f.atlas_relocated > 0;", "  f.atlas_replanned = false;"),
     "the lights' records carry the re-planned tiles but the backends' passes and read-backs keep the tiles allocated "
     "at configure", REPLAN),
    ("stale_face_never_refreshed", "backends/common/shadow_frame.cpp",
     replace("if (holds) continue;", "if (holds || face == 5) continue;"),
     "the update budget never finds a light's -Z face stale: after the first frame it keeps its first position",
     UPDATE),
    ("moving_casters_never_uploaded", "backends/registry.cpp",
     replace("  scene_->pose(frame);\n  upload_moving_objects();", "  scene_->pose(frame);"),
     "the posed moving casters never reach the device: both APIs draw them where the file put them", MOVING),
    ("mesh_spheres_at_rest", "backends/common/meshlets.cpp",
     replace("    if (!posed.objects[o].moves()) continue;", "    continue;"),
     "mesh_shader culls by the moving casters' meshlet spheres where load() built them, not where they are now",
     MESH),
    ("mesh_one_pass_layers_of_first_light", "shaders/mesh_common.glsl",
     replace("int meshlet_layer(uint light, int face) { return 6 * int(light) + face; }",
             "int meshlet_layer(uint light, int face) { return face; }"),
     "mesh_shader's one pass renders each light's faces into the first light's layers", MESH),
    ("mesh_task_culls_by_first_light", "shaders/mesh_common.glsl",
     replace("  return point_lights[light].position_far.xyz;", "  return point_lights[0].position_far.xyz;"),
     "mesh_shader's one pass culls every light's meshlets against the first light's frustums", MESH),
    ("dirty_rule_ignores_moving_casters", "backends/common/shadow_plan.cpp",
     replace("    if (!o.moves() || o.offset_at(then) == o.offset_at(now)) continue;", "    continue;"),
     "the dirty rule never sees a moving caster: a static cache keeps faces a roller or cart moved through", MOVING),
]

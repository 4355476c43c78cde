// gnomon's own passes, appended to the lookup module (lookup.wgsl, bind group 1).
//
// Depth pass (vs_depth / fs_depth): per map, the casters' linear light depth plus constant and
// slope-scaled bias, so that the bias is in world units whatever the map's warp; fs_depth_id
// also writes the caster's object ID (its instance index + 1) into the map's ID layer.
// Main pass (vs_main with fs_measured or fs_color): ambient plus Lambert per light, each
// light's shadow factor from its maps; fs_measured also writes the lit-light bits and the
// sampling metrics. Volume passes (vs_main_infinite with fs_ambient, fs_volume_lit,
// fs_volume_shadowed; vs_volume): exact shadows from stenciled shadow volumes.
// Light view (vs_fullscreen / fs_light_view): one map's depth as grey.

struct Frame {
    // View space to the camera's clip space: reversed Z (1 at the near plane, 0 at the far).
    clip_from_camera: mat4x4<f32>,
    // The same with the far plane at infinity (depth = near / distance; 0 at infinity).
    infinite_clip_from_camera: mat4x4<f32>,
    // x: ambient (0 to 1), y: 1 to tint pixels by the map they read (light 0's first map
    // blue, its second red).
    shading: vec4<f32>,
};

// One pass's slot (a dynamic offset): the map a depth pass draws, the light a volume pass lights.
struct Slot {
    map: u32,
    light: u32,
    unused_a: u32,
    unused_b: u32,
};

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<uniform> slot: Slot;

// Per instance: view from object (columns), its normal matrix (columns; w unused) and its
// colour (w: 1 where it receives shadows).
struct Instance {
    @location(3) c0: vec4<f32>,
    @location(4) c1: vec4<f32>,
    @location(5) c2: vec4<f32>,
    @location(6) c3: vec4<f32>,
    @location(7) n0: vec4<f32>,
    @location(8) n1: vec4<f32>,
    @location(9) n2: vec4<f32>,
    @location(10) color: vec4<f32>,
};

// Only the transform, for casters (an engine's casters have no gnomon colour or normals).
struct CasterInstance {
    @location(3) c0: vec4<f32>,
    @location(4) c1: vec4<f32>,
    @location(5) c2: vec4<f32>,
    @location(6) c3: vec4<f32>,
};

struct DepthOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) depth: f32,
    // The caster's object ID: its instance index + 1 (0 is "no caster").
    @location(1) @interpolate(flat) object: u32,
    // Texture coordinates, where the mesh has holes (vs_depth_cut).
    @location(2) uv: vec2<f32>,
    // A paraboloid map's (see depth_out): the point in the hemisphere's frame, q, and its place
    // in the map, both interpolated straight across the triangle's image.
    @location(3) q: vec3<f32>,
    @location(4) map_xy: vec2<f32>,
    // The map's bias (x: constant, y: slope scale, z: slope clamp) and, for a paraboloid
    // map, its scale (0 for other maps): read from its record once per vertex rather than
    // once per texel (a CPU rasteriser's depth passes took 1.3 to 1.45 times as long).
    @location(5) @interpolate(flat) bias: vec3<f32>,
    @location(6) @interpolate(flat) paraboloid_scale: f32,
    // The slope bias's cap in texel widths (x) and the map's depth units per world unit (y;
    // a paraboloid map's: its texel's angle, see paraboloid_slope_cap), with the point in view
    // space: the texel's width across the light, where the fragment lies, is the surface's
    // step between neighbouring texels less its part along the light.
    @location(7) @interpolate(flat) slope_cap: vec2<f32>,
    @location(8) camera: vec3<f32>,
};

// Group 2 of the main passes and of the depth passes with holes: the mesh's alpha (an
// alpha-masked material's), its sampler (bilinear, the material's wrap modes) and its cutoff
// in cutout_info.cutoff.x (0 for meshes without holes: nothing is below it).
struct CutoutInfo {
    cutoff: vec4<f32>,
};

@group(2) @binding(0) var cutout_alpha: texture_2d<f32>;
@group(2) @binding(1) var cutout_sampler: sampler;
@group(2) @binding(2) var<uniform> cutout_info: CutoutInfo;

// Whether the surface has a hole at texture coordinates uv.
fn is_hole(uv: vec2<f32>) -> bool {
    return textureSampleLevel(cutout_alpha, cutout_sampler, uv, 0.0).r < cutout_info.cutoff.x;
}

@vertex
fn vs_depth(@location(0) position: vec3<f32>, instance: CasterInstance, @builtin(instance_index) index: u32) -> DepthOut {
    return depth_out(position, instance, index);
}

// The depth pass of a scene with holes: the texture coordinates go along.
@vertex
fn vs_depth_cut(@location(0) position: vec3<f32>, @location(2) uv: vec2<f32>, instance: CasterInstance, @builtin(instance_index) index: u32) -> DepthOut {
    var out = depth_out(position, instance, index);
    out.uv = uv;
    return out;
}

fn depth_out(position: vec3<f32>, instance: CasterInstance, index: u32) -> DepthOut {
    let camera_from_object = mat4x4<f32>(instance.c0, instance.c1, instance.c2, instance.c3);
    let p = camera_from_object * vec4<f32>(position, 1.0);
    var out: DepthOut;
    out.object = index + 1u;
    out.uv = vec2<f32>(0.0);
    out.q = vec3<f32>(0.0);
    out.map_xy = vec2<f32>(0.0);
    let info = gnomon_shadows.maps[slot.map].info;
    out.bias = gnomon_shadows.maps[slot.map].bias.xyz;
    out.slope_cap = vec2<f32>(
        gnomon_shadows.maps[slot.map].slope_cap.x,
        length(gnomon_shadows.maps[slot.map].depth_from_camera.xyz),
    );
    out.camera = p.xyz;
    out.paraboloid_scale = 0.0;
    out.clip = gnomon_shadows.maps[slot.map].clip_from_camera * p;
    out.depth = dot(gnomon_shadows.maps[slot.map].depth_from_camera, p);
    if ((info.y & GNOMON_MAP_PARABOLOID) != 0u) {
        // The vertex's place in the paraboloid, its distance as the depth, and a clip z that
        // cuts the hemisphere at its rim (the edges between vertices stay straight: the
        // technique's known error at silhouettes). Inside the triangle the fragment shader
        // takes the depth of its own direction (paraboloid_depth).
        let q = out.clip.xyz;
        let d = max(length(q), 1e-30);
        let xy = q.xy * (gnomon_paraboloid_scale(info) / max(d + q.z, 1e-6 * d));
        out.clip = vec4<f32>(xy, (q.z / d - GNOMON_PARABOLOID_RIM) / (1.0 - GNOMON_PARABOLOID_RIM), 1.0);
        out.depth = d;
        out.q = q;
        out.map_xy = xy;
        out.paraboloid_scale = gnomon_paraboloid_scale(info);
        out.slope_cap.y = paraboloid_texel_angle(info);
    }
    return out;
}

// A paraboloid map's texel width as an angle at its centre, times 1 + |a|^2 (a: the place in
// the map over its scale): the map is a stereographic projection of the hemisphere, a
// direction at angle theta from the axis at |a| = tan(theta / 2), so one texel (2 / resolution
// of the map's [-1, 1]) spans 4 / (resolution scale (1 + |a|^2)) radians, in every direction
// (the projection is conformal).
fn paraboloid_texel_angle(info: vec4<u32>) -> f32 {
    return 4.0 / (f32(info.z) * gnomon_paraboloid_scale(info));
}

// A paraboloid map's slope bias's clamp at a texel whose ray, along the place a, hits at
// distance `depth` (in units of the light's range: the map's depth): bias.z, raised to
// `slope_cap.x` texel widths across the ray there (`slope_cap.y`: paraboloid_texel_angle).
fn paraboloid_slope_cap(depth: f32, a: vec2<f32>, bias: vec3<f32>, slope_cap: vec2<f32>) -> f32 {
    return max(bias.z, slope_cap.x * depth * slope_cap.y / (1.0 + dot(a, a)));
}

// A paraboloid map's depth at a fragment: the distance, along the direction of the
// fragment's place in the map, to the plane of the triangle (x), and whether that direction
// meets the plane in front of the light and not far beyond its range (y: 1, else 0; depths
// beyond the range clamp to the far end and shadow nothing). Distances
// interpolated between the vertices are wrong inside a large triangle (a wall's two triangles
// beside a lamp shadow in the wrong place), and a fragment whose direction does not meet the
// plane where it can is not the triangle's (its straight edges cover places the paraboloid's
// curved ones do not). The interpolated q lies on the triangle's plane and its screen
// derivatives span it; where they do not (a triangle seen edge on: y is 1) the interpolated
// distance stands.
fn paraboloid_depth(in: DepthOut) -> vec2<f32> {
    let dx = dpdx(in.q);
    let dy = dpdy(in.q);
    let n = cross(dx, dy);
    // The unit direction of map place f: f / k = v.xy / (1 + v.z), so with a = f / k,
    // v = (2 a, 1 - |a|^2) / (1 + |a|^2).
    let a = in.map_xy / max(in.paraboloid_scale, 1e-30);
    let aa = dot(a, a);
    let v = vec3<f32>(2.0 * a, 1.0 - aa) / (1.0 + aa);
    let along = dot(n, v);
    let t = dot(n, in.q) / along;
    let spanned = length(n) > 1e-3 * length(dx) * length(dy);
    let meets = abs(along) > 1e-5 * length(n) && t > 0.0 && t <= 2.0;
    return select(vec2<f32>(in.depth, 1.0), vec2<f32>(t, select(0.0, 1.0, meets)), spanned);
}

// The biased depth a depth pass writes; discards a paraboloid map's fragment that is not its
// triangle's (see paraboloid_depth).
fn biased_depth(in: DepthOut) -> f32 {
    let paraboloid = in.paraboloid_scale > 0.0;
    let exact = select(vec2<f32>(in.depth, 1.0), paraboloid_depth(in), paraboloid);
    let a = in.map_xy / max(in.paraboloid_scale, 1e-30);
    let cap = select(texel_slope_cap(exact.x, in), paraboloid_slope_cap(exact.x, a, in.bias, in.slope_cap), paraboloid);
    let depth = with_capped_bias(exact.x, in.bias, cap);
    if (exact.y == 0.0) {
        discard;
    }
    return depth;
}

// `depth` with the map's bias (x: constant, y: slope scale; z: slope clamp, here `cap` in
// depth units, which the callers raise with the texels): the slope is the depth change across
// one texel (the pass renders texels). Call it before any discard (it takes screen
// derivatives).
fn with_capped_bias(depth: f32, bias: vec3<f32>, cap: f32) -> f32 {
    let slope = max(abs(dpdx(depth)), abs(dpdy(depth)));
    return clamp(depth + bias.x + min(bias.y * slope, cap), 0.0, 1.0);
}

// The slope bias's clamp at a depth pass's fragment: bias.z, raised to in.slope_cap.x texel
// widths where that is larger. The texel's width across the light is the surface's step to
// the next texel less its part along the light (the depth's step over the depth units per
// world unit). Takes screen derivatives.
fn texel_slope_cap(depth: f32, in: DepthOut) -> f32 {
    let along = vec2<f32>(dpdx(depth), dpdy(depth)) / max(in.slope_cap.y, 1e-30);
    let dx = dpdx(in.camera);
    let dy = dpdy(in.camera);
    let across_sq = max(dot(dx, dx) - along.x * along.x, dot(dy, dy) - along.y * along.y);
    return max(in.bias.z, in.slope_cap.x * sqrt(max(across_sq, 0.0)) * in.slope_cap.y);
}

@fragment
fn fs_depth(in: DepthOut) -> @builtin(frag_depth) f32 {
    return biased_depth(in);
}

struct DepthIdOut {
    @builtin(frag_depth) depth: f32,
    @location(0) object: vec4<u32>,
};

// The depth pass of a frame that reads object IDs: the nearest caster's ID wins the texel with
// its depth.
@fragment
fn fs_depth_id(in: DepthOut) -> DepthIdOut {
    return DepthIdOut(biased_depth(in), vec4<u32>(in.object, 0u, 0u, 0u));
}

// The depth passes of a scene with holes: a hole casts no shadow.
@fragment
fn fs_depth_cut(in: DepthOut) -> @builtin(frag_depth) f32 {
    let depth = biased_depth(in);
    if (is_hole(in.uv)) {
        discard;
    }
    return depth;
}

@fragment
fn fs_depth_id_cut(in: DepthOut) -> DepthIdOut {
    let depth = biased_depth(in);
    if (is_hole(in.uv)) {
        discard;
    }
    return DepthIdOut(depth, vec4<u32>(in.object, 0u, 0u, 0u));
}

// The exact paraboloid depth pass (vs_paraboloid / fs_paraboloid*): where the device has
// storage buffers in vertex shaders, a paraboloid map's triangles are not drawn between their
// corners' places. Each vertex reads its triangle's three corners (group 3: the scene's
// vertices, eight f32 each with the position first and the texture coordinates last, and its
// indices, counted from the first vertex), and the three vertices draw one triangle that
// covers the hemisphere's image of the whole triangle; each texel of it casts its own ray from
// the light at the triangle and keeps the distance where it hits (Moller and Trumbore's
// test). The edges are then the curves they are in the map, a triangle that crosses the rim
// is drawn on both sides of it, and the depth is the texel's own.
@group(3) @binding(0) var<storage, read> scene_vertices: array<f32>;
@group(3) @binding(1) var<storage, read> scene_indices: array<u32>;

// Floats per vertex in scene_vertices (gnomon-render's Vertex: position, normal, uv).
const VERTEX_FLOATS: u32 = 8u;

// The ray test (Moller and Trumbore's, from the light at the origin of the hemisphere's frame)
// against corners q0, q1, q2 (in units of the light's range) along direction v: with
// e1 = q1 - q0, e2 = q2 - q0 and s = -q0, det = v . (e2 x e1), the barycentric weights of
// corners 1 and 2 are v . (e2 x s) / det and v . (s x e1) / det, and the distance is
// e2 . (s x e1) / det. Everything but v is the triangle's, computed once by its vertices. The
// weights are the same for any length of v, so the fragment takes v = (2 a, 1 - |a|^2) (of
// length 1 + |a|^2) and scales the distance back.
struct ParaboloidOut {
    @builtin(position) clip: vec4<f32>,
    // The place in the map divided by the map's scale (a: the direction is
    // (2 a, 1 - |a|^2) / (1 + |a|^2)), linear across the covering triangle.
    @location(0) a: vec2<f32>,
    // e2 x e1, and its length.
    @location(1) @interpolate(flat) normal: vec4<f32>,
    // e2 x s, and e2 . (s x e1).
    @location(2) @interpolate(flat) weight_1: vec4<f32>,
    // s x e1.
    @location(3) @interpolate(flat) weight_2: vec3<f32>,
    @location(4) @interpolate(flat) object: u32,
    // The corners' texture coordinates (uv0, uv1; uv2), for holes.
    @location(5) @interpolate(flat) uv01: vec4<f32>,
    @location(6) @interpolate(flat) uv2: vec2<f32>,
    // The map's bias (its record's, read once per vertex rather than per texel).
    @location(7) @interpolate(flat) bias: vec3<f32>,
    // The slope bias's cap in texel widths and the texel's angle (paraboloid_slope_cap).
    @location(8) @interpolate(flat) slope_cap: vec2<f32>,
};

// Corner `c` (0, 1, 2) of a triangle that covers the map's image of the triangle whose corners
// are q[0..3] (in normalised device coordinates); all three at one place where the triangle
// lies wholly behind the rim (nothing to draw). The map is a stereographic projection, which
// takes circles to circles, so the image is bounded by three circular arcs: the smaller of
// two covers is drawn, the triangle of the corners' places with each edge moved out by its
// arc's bulge (tight for small triangles), or the triangle around the disc that is the image
// of a spherical cap holding the triangle's directions (for triangles wide or reaching behind
// the rim); else the whole map.
fn paraboloid_cover(q: array<vec3<f32>, 3>, k: f32, c: u32) -> vec2<f32> {
    var n: array<vec3<f32>, 3>;
    var behind = true;
    var in_front = true;
    var tiny = false;
    for (var i = 0u; i < 3u; i++) {
        let d = length(q[i]);
        tiny = tiny || d < 1e-6;
        n[i] = q[i] / max(d, 1e-30);
        behind = behind && n[i].z < GNOMON_PARABOLOID_RIM;
        in_front = in_front && n[i].z > GNOMON_PARABOLOID_RIM;
    }
    // A corner at the light has no direction: the whole map.
    if (tiny) {
        return box_cover(vec2<f32>(-1.0), vec2<f32>(1.0), c);
    }
    // Directions wholly behind the rim stay behind it between the corners (a cap smaller than
    // a hemisphere is convex on the sphere).
    if (behind) {
        return vec2<f32>(4.0);
    }
    // The whole map's cover, then the cap's, then the grown triangle's, each kept where it is
    // smaller (area: twice the triangle's).
    var best = box_cover(vec2<f32>(-1.0), vec2<f32>(1.0), c);
    var best_area = 16.0;
    let cap = cap_cover(n, k, c);
    if (cap.w < best_area) {
        best = cap.xy;
        best_area = cap.w;
    }
    if (in_front) {
        let grown = grown_cover(n, k, c);
        if (grown.w < best_area) {
            best = grown.xy;
        }
    }
    return best;
}

// The cap cover (see paraboloid_cover): corner `c` in xy, twice its area in w (infinite where
// the cap is too wide or reaches around to the far pole). A cap of centre m and angular
// radius rho, at angle theta from the hemisphere's axis, spans tan((theta - rho) / 2) to
// tan((theta + rho) / 2) along m's azimuth.
fn cap_cover(n: array<vec3<f32>, 3>, k: f32, c: u32) -> vec4<f32> {
    let sum = n[0] + n[1] + n[2];
    let centre = sum / max(length(sum), 1e-30);
    // The cap's radius from the longest chord (exact for small caps, where acos of a cosine
    // near 1 is not), grown a little for rounding.
    let chord = max(max(length(n[0] - centre), length(n[1] - centre)), length(n[2] - centre));
    let rho = 2.0 * asin(min(0.5 * chord, 1.0)) + 1e-5;
    let theta = atan2(length(centre.xy), centre.z);
    if (length(sum) <= 1e-3 || rho >= 1.5 || theta + rho >= 2.9) {
        return vec4<f32>(0.0, 0.0, 0.0, 1e30);
    }
    let r0 = tan(0.5 * (theta - rho));
    let r1 = tan(0.5 * (theta + rho));
    let along = centre.xy / max(length(centre.xy), 1e-30);
    let mid = k * 0.5 * (r0 + r1) * along;
    // Grown by a thousandth and a tenth of a texel of the largest map.
    let radius = k * 0.5 * (r1 - r0) * 1.001 + 1e-4;
    if (all(abs(mid) + radius <= vec2<f32>(1.0))) {
        // Inside the map: the equilateral triangle around the disc (its corners at twice the
        // radius).
        let angle = 2.0943951 * f32(c) + 1.5707963;
        return vec4<f32>(mid + 2.0 * radius * vec2<f32>(cos(angle), sin(angle)), 0.0, 10.392305 * radius * radius);
    }
    let lo = max(mid - vec2<f32>(radius), vec2<f32>(-1.0));
    let hi = min(mid + vec2<f32>(radius), vec2<f32>(1.0));
    let size = max(hi - lo, vec2<f32>(0.0));
    return vec4<f32>(box_cover(lo, hi, c), 0.0, 4.0 * size.x * size.y);
}

// The grown cover (see paraboloid_cover) of a triangle whose corners lie inside the rim:
// corner `c` in xy, twice its area in w (infinite where an edge's arc is more than half its
// circle, or the grown triangle is degenerate). The great circle through directions a and b,
// of normal m = a x b, lands on the circle of centre m.xy / m.z and radius |m| / |m.z|; an
// arc less than half of it lies within its sagitta (h^2 / (R + sqrt(R^2 - h^2)), h half the
// chord) of the chord, on the side away from the centre.
fn grown_cover(n: array<vec3<f32>, 3>, k: f32, c: u32) -> vec4<f32> {
    let none = vec4<f32>(0.0, 0.0, 0.0, 1e30);
    var p: array<vec2<f32>, 3>;
    for (var i = 0u; i < 3u; i++) {
        p[i] = k * n[i].xy / (1.0 + n[i].z);
    }
    let area = (p[1].x - p[0].x) * (p[2].y - p[0].y) - (p[1].y - p[0].y) * (p[2].x - p[0].x);
    if (abs(area) <= 1e-12) {
        return none;
    }
    // Each edge's line as (outward normal, offset): inside where dot(normal, x) <= offset.
    var lines: array<vec3<f32>, 3>;
    for (var i = 0u; i < 3u; i++) {
        let j = (i + 1u) % 3u;
        let a = p[i];
        let e = p[j] - a;
        let length_e = length(e);
        if (length_e <= 0.0) {
            return none;
        }
        let o = sign(area) * vec2<f32>(e.y, -e.x) / length_e;
        // The arc's side (its geodesic midpoint's place) and its centre's.
        let h = normalize(n[i] + n[j]);
        let side = dot(o, k * h.xy / (1.0 + h.z) - a);
        let m = cross(n[i], n[j]);
        var grow = max(side, 0.0);
        if (abs(m.z) > 1e-6 * length(m)) {
            let centre = dot(o, k * m.xy / m.z - a);
            if (centre * side > 0.0) {
                // The arc and its circle's centre on one side: more than half the circle.
                return none;
            }
            if (side > 0.0) {
                let radius = k * length(m) / abs(m.z);
                let half = 0.5 * length_e;
                grow = max(grow, half * half / (radius + sqrt(max(radius * radius - half * half, 0.0))));
            }
        }
        lines[i] = vec3<f32>(o, dot(o, a) + grow * 1.001 + 1e-4);
    }
    // Corner i meets edges i - 1 and i.
    var corner: array<vec2<f32>, 3>;
    for (var i = 0u; i < 3u; i++) {
        let l0 = lines[(i + 2u) % 3u];
        let l1 = lines[i];
        let det = l0.x * l1.y - l0.y * l1.x;
        if (abs(det) <= 1e-6) {
            return none;
        }
        corner[i] = vec2<f32>(l0.z * l1.y - l1.z * l0.y, l0.x * l1.z - l1.x * l0.z) / det;
    }
    let grown = abs((corner[1].x - corner[0].x) * (corner[2].y - corner[0].y) - (corner[1].y - corner[0].y) * (corner[2].x - corner[0].x));
    return vec4<f32>(corner[c], 0.0, grown);
}

// Corner `c` of a right triangle with legs twice the box's sides, which holds the box.
fn box_cover(lo: vec2<f32>, hi: vec2<f32>, c: u32) -> vec2<f32> {
    let size = max(hi - lo, vec2<f32>(0.0));
    return select(select(lo, lo + vec2<f32>(2.0 * size.x, 0.0), c == 1u), lo + vec2<f32>(0.0, 2.0 * size.y), c == 2u);
}

@vertex
fn vs_paraboloid(@builtin(vertex_index) vertex: u32, instance: CasterInstance, @builtin(instance_index) index: u32) -> ParaboloidOut {
    let camera_from_object = mat4x4<f32>(instance.c0, instance.c1, instance.c2, instance.c3);
    let map = gnomon_shadows.maps[slot.map];
    let first = vertex - vertex % 3u;
    var q: array<vec3<f32>, 3>;
    var uv: array<vec2<f32>, 3>;
    for (var i = 0u; i < 3u; i++) {
        let at = VERTEX_FLOATS * scene_indices[first + i];
        let position = vec3<f32>(scene_vertices[at], scene_vertices[at + 1u], scene_vertices[at + 2u]);
        q[i] = (map.clip_from_camera * (camera_from_object * vec4<f32>(position, 1.0))).xyz;
        uv[i] = vec2<f32>(scene_vertices[at + 6u], scene_vertices[at + 7u]);
    }
    let k = gnomon_paraboloid_scale(map.info);
    let xy = paraboloid_cover(q, k, vertex % 3u);
    var out: ParaboloidOut;
    out.clip = vec4<f32>(xy, 0.5, 1.0);
    out.a = xy / k;
    let e1 = q[1] - q[0];
    let e2 = q[2] - q[0];
    let normal = cross(e2, e1);
    let across = cross(-q[0], e1);
    out.normal = vec4<f32>(normal, length(normal));
    out.weight_1 = vec4<f32>(cross(e2, -q[0]), dot(e2, across));
    out.weight_2 = across;
    out.object = index + 1u;
    out.bias = map.bias.xyz;
    out.slope_cap = vec2<f32>(map.slope_cap.x, paraboloid_texel_angle(map.info));
    out.uv01 = vec4<f32>(uv[0], uv[1]);
    out.uv2 = uv[2];
    return out;
}

// Where the texel's ray meets the triangle: (distance from the light in units of its range,
// barycentric weights of corners 1 and 2); w is 1 where the ray hits the triangle (edges
// grown by a ten-thousandth, so that neighbours leave no crack), else 0. The distance is to
// the triangle's plane wherever the ray meets it, so that its screen derivatives (the slope
// bias) are the plane's at the triangle's edges too.
fn paraboloid_hit(in: ParaboloidOut) -> vec4<f32> {
    let aa = dot(in.a, in.a);
    let v = vec3<f32>(2.0 * in.a, 1.0 - aa);
    let det = dot(v, in.normal.xyz);
    let inv = 1.0 / select(det, 1e-30, det == 0.0);
    let b1 = dot(v, in.weight_1.xyz) * inv;
    let b2 = dot(v, in.weight_2) * inv;
    let t = in.weight_1.w * (1.0 + aa) * inv;
    let slack = 1e-4;
    let hit = abs(det) > 1e-12 * in.normal.w * (1.0 + aa) && t > 0.0 && b1 >= -slack
        && b2 >= -slack && b1 + b2 <= 1.0 + slack;
    return vec4<f32>(t, b1, b2, select(0.0, 1.0, hit));
}

// The biased depth of the texel's hit (x) and the hit's barycentric weights of corners 1 and 2
// (y, z); discards a texel whose ray misses the triangle.
fn paraboloid_texel(in: ParaboloidOut) -> vec3<f32> {
    let hit = paraboloid_hit(in);
    let depth = with_capped_bias(hit.x, in.bias, paraboloid_slope_cap(hit.x, in.a, in.bias, in.slope_cap));
    if (hit.w == 0.0) {
        discard;
    }
    return vec3<f32>(depth, hit.yz);
}

// Whether the hit (barycentric weights of corners 1 and 2) is in a hole of the mesh.
fn paraboloid_hole(in: ParaboloidOut, b: vec2<f32>) -> bool {
    return is_hole((1.0 - b.x - b.y) * in.uv01.xy + b.x * in.uv01.zw + b.y * in.uv2);
}

@fragment
fn fs_paraboloid(in: ParaboloidOut) -> @builtin(frag_depth) f32 {
    return paraboloid_texel(in).x;
}

@fragment
fn fs_paraboloid_id(in: ParaboloidOut) -> DepthIdOut {
    return DepthIdOut(paraboloid_texel(in).x, vec4<u32>(in.object, 0u, 0u, 0u));
}

@fragment
fn fs_paraboloid_cut(in: ParaboloidOut) -> @builtin(frag_depth) f32 {
    let hit = paraboloid_texel(in);
    if (paraboloid_hole(in, hit.yz)) {
        discard;
    }
    return hit.x;
}

@fragment
fn fs_paraboloid_id_cut(in: ParaboloidOut) -> DepthIdOut {
    let hit = paraboloid_texel(in);
    if (paraboloid_hole(in, hit.yz)) {
        discard;
    }
    return DepthIdOut(hit.x, vec4<u32>(in.object, 0u, 0u, 0u));
}

struct MainOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) camera: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) color: vec4<f32>,
    // Clip z and w: their ratio is the depth, for the `_frag_depth` entry points (GL, where
    // wgpu maps clip z to [-1, 1] with z * 2 - w, which cancels reversed Z's precision far
    // away; the ratio of the interpolated pair is exact).
    @location(3) depth: vec2<f32>,
    // The object's ID (its instance index + 1), as the depth pass writes it.
    @location(4) @interpolate(flat) object: u32,
    // Texture coordinates (where the mesh has holes).
    @location(5) uv: vec2<f32>,
};

fn main_out(position: vec3<f32>, normal: vec3<f32>, uv: vec2<f32>, instance: Instance, index: u32, clip_from_camera: mat4x4<f32>) -> MainOut {
    let camera_from_object = mat4x4<f32>(instance.c0, instance.c1, instance.c2, instance.c3);
    let normal_matrix = mat3x3<f32>(instance.n0.xyz, instance.n1.xyz, instance.n2.xyz);
    var out: MainOut;
    let p = camera_from_object * vec4<f32>(position, 1.0);
    out.clip = clip_from_camera * p;
    out.depth = out.clip.zw;
    out.camera = p.xyz;
    out.normal = normal_matrix * normal;
    out.color = instance.color;
    out.object = index + 1u;
    out.uv = uv;
    return out;
}

@vertex
fn vs_main(@location(0) position: vec3<f32>, @location(1) normal: vec3<f32>, @location(2) uv: vec2<f32>, instance: Instance, @builtin(instance_index) index: u32) -> MainOut {
    return main_out(position, normal, uv, instance, index, frame.clip_from_camera);
}

@vertex
fn vs_main_infinite(@location(0) position: vec3<f32>, @location(1) normal: vec3<f32>, @location(2) uv: vec2<f32>, instance: Instance, @builtin(instance_index) index: u32) -> MainOut {
    return main_out(position, normal, uv, instance, index, frame.infinite_clip_from_camera);
}

// Pipeline specialisations: the sampling metrics (fs_measured), the number of lights (a loop
// with a constant trip count costs far less than one bounded by a uniform on some devices:
// 1.4x the main pass on lavapipe).
override METRICS: bool = false;
override LIGHT_COUNT: u32 = 1u;
// Whether a light picks its map per pixel: cascades (with their blend band and fade) or a
// point light's cube faces.
override PER_PIXEL: bool = false;
// How the maps are read: GNOMON_READ_DEPTH, GNOMON_READ_OBJECT_ID or GNOMON_READ_ID_DEPTH.
override MAP_READ: u32 = 0u;
// Whether the scene has holes (alpha-masked meshes): the main pass discards them.
override CUTOUT: bool = false;

// A fragment's surface: geometric normal (the triangle's plane) and shading normal, both
// turned toward the camera (at the origin of view space).
struct Surface {
    p: vec3<f32>,
    // The fragment's position in the target (pixels), for dithering.
    pixel: vec2<f32>,
    n_geo: vec3<f32>,
    n: vec3<f32>,
    receives: bool,
    // Its object's ID (object-ID reads).
    object: u32,
};

fn surface(in: MainOut, dp_dx: vec3<f32>, dp_dy: vec3<f32>) -> Surface {
    var s: Surface;
    s.p = in.camera;
    s.pixel = in.clip.xy;
    s.n_geo = normalize(cross(dp_dx, dp_dy));
    let to_eye = -in.camera;
    if (dot(s.n_geo, to_eye) < 0.0) {
        s.n_geo = -s.n_geo;
    }
    s.n = normalize(in.normal);
    if (dot(s.n, to_eye) < 0.0) {
        s.n = -s.n;
    }
    s.receives = in.color.w > 0.5;
    s.object = in.object;
    return s;
}

// The map light 0 reads at p, as the main pass is specialised (for the tint and metrics).
fn main_map_index(light: u32, p: vec3<f32>) -> u32 {
    if (PER_PIXEL) {
        return gnomon_select(light, p).map;
    }
    return gnomon_plane_map_index(light, p);
}

// Interleaved gradient noise in [0, 1) (Jimenez 2014): a threshold per pixel that is
// spread evenly over small neighbourhoods.
fn gnomon_dither(pixel: vec2<f32>) -> f32 {
    return fract(52.9829189 * fract(dot(pixel, vec2<f32>(0.06711056, 0.00583715))));
}

struct Shaded {
    color: vec3<f32>,
    // Bit k: light k reaches the point (one tap).
    lit_bits: u32,
    // N.L of light 0 (geometric normal).
    n_dot_l: f32,
    // Light 0's filtered shadow factor (1 lit; 1 where the surface receives none).
    shadow: f32,
    // Whether light 0's one-tap lookup may be wrong (measured frames only).
    unsure: bool,
};

fn shade(s: Surface, albedo: vec3<f32>) -> Shaded {
    var out: Shaded;
    let ambient = frame.shading.x;
    var direct = 0.0;
    out.lit_bits = 0u;
    out.n_dot_l = 0.0;
    out.shadow = 1.0;
    out.unsure = false;
    for (var light = 0u; light < LIGHT_COUNT; light++) {
        let incidence = gnomon_incidence(light, s.p);
        let n_dot_l_geo = dot(s.n_geo, incidence.to_light);
        if (light == 0u) {
            out.n_dot_l = n_dot_l_geo;
        }
        var one_tap = 1.0;
        var shadow = 1.0;
        if (s.receives) {
            // In a cascade's blend band the next map takes over for a share of the pixels
            // that grows across the band, dithered by the pixel: one lookup, where mixing two
            // maps would cost every pixel a second filter on a CPU rasteriser (which samples
            // in masked-off branches too). Without cascades the map stays the same for every
            // pixel of a draw, which keeps the reads of its record scalar.
            var map = gnomon_plane_map_index(light, s.p);
            var fade = 0.0;
            if (PER_PIXEL) {
                let selected = gnomon_select(light, s.p);
                map = select(
                    selected.map, selected.map + 1u, selected.next_weight > gnomon_dither(s.pixel));
                fade = selected.fade;
            }
            let at = gnomon_read_at(light, map, s.p, s.n_geo, n_dot_l_geo);
            if (at.covered && MAP_READ == GNOMON_READ_DEPTH) {
                one_tap = gnomon_lookup_view(at.view, at.point, GNOMON_FILTER_ONE_TAP);
                if (METRICS && light == 0u) {
                    out.unsure = !gnomon_lookup_sure(at.view, at.point);
                }
                if (gnomon_shadows.info.y == GNOMON_FILTER_PCSS) {
                    shadow = gnomon_lookup_pcss(light, at.view, at.point, s.n_geo);
                } else {
                    shadow = gnomon_lookup_view(at.view, at.point, gnomon_shadows.info.y);
                }
            } else if (at.covered) {
                // Object IDs read the point itself, without the normal offset: nothing is
                // compared between objects, and an offset along the normal moves the read
                // across the outline of the point's object as the light sees it, into the
                // texels of what lies beside it (IDs and depth, read at the offset point:
                // 0.50% wrong pixels over compare's demo views against 0.20% here).
                one_tap = gnomon_lookup_ids(at.view, s.p, s.object, MAP_READ, GNOMON_FILTER_ONE_TAP);
                shadow = gnomon_lookup_ids(at.view, s.p, s.object, MAP_READ, gnomon_shadows.info.y);
            }
            if (PER_PIXEL) {
                // Shadows fade toward the shadow distance in the picture; the one-tap mask
                // says what the maps hold, which they do out to that distance.
                shadow = mix(shadow, 1.0, fade);
                if (fade >= 1.0) {
                    one_tap = 1.0;
                }
            }
        }
        if (light == 0u) {
            out.shadow = shadow;
        }
        if (incidence.in_light) {
            direct += max(dot(s.n, incidence.to_light), 0.0) * incidence.cone * shadow;
        }
        if (incidence.in_light && n_dot_l_geo > 0.0 && one_tap > 0.5) {
            out.lit_bits |= 1u << light;
        }
    }
    var tint = vec3<f32>(1.0);
    if (frame.shading.y > 0.5 && gnomon_shadows.info.x > 0u && gnomon_shadows.lights[0].info.w >= 2u) {
        // Light 0's maps: the first blue, the second red (SPPSM's two), then the cascades'.
        let palette = array<vec3<f32>, 8>(
            vec3<f32>(0.55, 0.7, 1.0), vec3<f32>(1.0, 0.55, 0.5), vec3<f32>(0.55, 1.0, 0.55),
            vec3<f32>(1.0, 0.9, 0.45), vec3<f32>(0.85, 0.55, 1.0), vec3<f32>(0.45, 1.0, 1.0),
            vec3<f32>(1.0, 0.7, 0.3), vec3<f32>(0.75, 0.75, 0.75));
        let k = main_map_index(0u, s.p) - gnomon_shadows.lights[0].info.z;
        tint = palette[min(k, 7u)];
    }
    out.color = albedo * (ambient + (1.0 - ambient) * direct) * tint;
    return out;
}

// The Jacobian J of light 0's map's texel coordinates by screen pixels at a point, reduced to
// (1 / sigma_min, 1 / |det J|): the map's analytic gradient times the fragment's position
// derivatives (so no derivative crosses from one map to another).
fn sampling_metrics(p: vec3<f32>, dp_dx: vec3<f32>, dp_dy: vec3<f32>) -> vec2<f32> {
    if (gnomon_shadows.info.x == 0u) {
        return vec2<f32>(-1.0, -1.0);
    }
    if (PER_PIXEL && gnomon_select(0u, p).fade >= 1.0) {
        // Beyond the cascades' shadow distance, or a cube face without a map.
        return vec2<f32>(-1.0, -1.0);
    }
    let map = main_map_index(0u, p);
    if ((gnomon_shadows.maps[map].clip_from_camera * vec4<f32>(p, 1.0)).w <= 0.0) {
        return vec2<f32>(-1.0, -1.0);
    }
    let view = gnomon_map_view(map);
    let g = gnomon_ndc_gradients(view, p);
    let scale = 0.5 * view.resolution;
    let jx = scale * vec2<f32>(dot(g[0], dp_dx), dot(g[1], dp_dx));
    let jy = scale * vec2<f32>(dot(g[0], dp_dy), dot(g[1], dp_dy));
    // J^T J = [[a, b], [b, c]]: its eigenvalues are the squared singular values.
    let a = dot(jx, jx);
    let b = dot(jx, jy);
    let c = dot(jy, jy);
    let root = sqrt(max(0.25 * (a - c) * (a - c) + b * b, 0.0));
    let sigma_min = sqrt(max(0.5 * (a + c) - root, 0.0));
    let det = abs(jx.x * jy.y - jx.y * jy.x);
    // At most a million pixels per texel: a surface edge-on to the light is not resolved.
    return vec2<f32>(1.0 / max(sigma_min, 1e-6), 1.0 / max(det, 1e-6));
}

struct Measured {
    @location(0) color: vec4<f32>,
    // x: bits 0..30, the lights that reach the point; bit 31: geometry here. y: light 0's
    // filtered shadow factor, as the bits of an f32.
    @location(1) lit: vec4<u32>,
    // The bits of four floats (integer targets render on every backend): x: pixels per
    // texel along the worst direction, y: in area (-1 where the map does not see the point),
    // z: N.L of light 0 (geometric normal toward the camera), w: 1, or 2 where light 0's
    // one-tap lookup may be wrong (gnomon_lookup_sure).
    @location(2) metrics: vec4<u32>,
};

// The camera sees through a mesh's holes (scenes that have them: CUTOUT).
fn cut(in: MainOut) {
    if (CUTOUT && is_hole(in.uv)) {
        discard;
    }
}

@fragment
fn fs_measured(in: MainOut) -> Measured {
    return measured(in);
}

struct MeasuredDepth {
    @location(0) color: vec4<f32>,
    @location(1) lit: vec4<u32>,
    @location(2) metrics: vec4<u32>,
    @builtin(frag_depth) depth: f32,
};

@fragment
fn fs_measured_frag_depth(in: MainOut) -> MeasuredDepth {
    let m = measured(in);
    return MeasuredDepth(m.color, m.lit, m.metrics, in.depth.x / in.depth.y);
}

fn measured(in: MainOut) -> Measured {
    let dp_dx = dpdxFine(in.camera);
    let dp_dy = dpdyFine(in.camera);
    cut(in);
    let s = surface(in, dp_dx, dp_dy);
    let shaded = shade(s, in.color.rgb);
    var out: Measured;
    out.color = vec4<f32>(shaded.color, 1.0);
    out.lit = vec4<u32>(shaded.lit_bits | 0x80000000u, bitcast<u32>(shaded.shadow), 0u, 0u);
    var sampling = vec2<f32>(0.0);
    if (METRICS) {
        sampling = sampling_metrics(s.p, dp_dx, dp_dy);
    }
    out.metrics = bitcast<vec4<u32>>(vec4<f32>(sampling, shaded.n_dot_l, select(1.0, 2.0, shaded.unsure)));
    return out;
}

fn color(in: MainOut) -> vec4<f32> {
    let dp_dx = dpdx(in.camera);
    let dp_dy = dpdy(in.camera);
    cut(in);
    let s = surface(in, dp_dx, dp_dy);
    return vec4<f32>(shade(s, in.color.rgb).color, 1.0);
}

@fragment
fn fs_color(in: MainOut) -> @location(0) vec4<f32> {
    return color(in);
}

struct ColorDepth {
    @location(0) color: vec4<f32>,
    @builtin(frag_depth) depth: f32,
};

@fragment
fn fs_color_frag_depth(in: MainOut) -> ColorDepth {
    return ColorDepth(color(in), in.depth.x / in.depth.y);
}

// Shadow volumes. The colour target blends additively; the mask target is the light's own
// (R8: 1 lit, 0 not lit).
struct VolumeOut {
    @location(0) color: vec4<f32>,
    @location(1) mask: vec4<f32>,
};

struct VolumeDepthOut {
    @location(0) color: vec4<f32>,
    @location(1) mask: vec4<f32>,
    @builtin(frag_depth) depth: f32,
};

fn with_depth(out: VolumeOut, in: MainOut) -> VolumeDepthOut {
    return VolumeDepthOut(out.color, out.mask, in.depth.x / in.depth.y);
}

// The volume passes draw the scene through the infinite projection (the volumes' caps at
// infinity are never clipped), so they drop what lies beyond the camera's far plane
// themselves: the picture shows what the maps' passes, clipped at the far plane, show.
fn discard_beyond_far(p: vec3<f32>) {
    if ((frame.clip_from_camera * vec4<f32>(p, 1.0)).z < 0.0) {
        discard;
    }
}

// The ambient term; the mask as if no light reached (the lights' passes write where they do).
fn ambient(in: MainOut) -> VolumeOut {
    discard_beyond_far(in.camera);
    var out: VolumeOut;
    out.color = vec4<f32>(in.color.rgb * frame.shading.x, 1.0);
    out.mask = vec4<f32>(0.0, 0.0, 0.0, 1.0);
    return out;
}

@fragment
fn fs_ambient(in: MainOut) -> VolumeOut {
    return ambient(in);
}

@fragment
fn fs_ambient_frag_depth(in: MainOut) -> VolumeDepthOut {
    return with_depth(ambient(in), in);
}

fn volume_direct(in: MainOut, shadowed: bool) -> VolumeOut {
    let s = surface(in, dpdx(in.camera), dpdy(in.camera));
    discard_beyond_far(in.camera);
    let incidence = gnomon_incidence(slot.light, s.p);
    let n_dot_l_geo = dot(s.n_geo, incidence.to_light);
    // Instances that receive no shadows are lit wherever the stencil says.
    let blocked = shadowed && s.receives;
    var direct = 0.0;
    if (incidence.in_light && !blocked) {
        direct = max(dot(s.n, incidence.to_light), 0.0) * incidence.cone;
    }
    let lit = incidence.in_light && n_dot_l_geo > 0.0 && !blocked;
    var out: VolumeOut;
    out.color = vec4<f32>(in.color.rgb * (1.0 - frame.shading.x) * direct, 1.0);
    out.mask = vec4<f32>(select(0.0, 1.0, lit), 0.0, 0.0, 1.0);
    return out;
}

// Where the light's stencil count is 0.
@fragment
fn fs_volume_lit(in: MainOut) -> VolumeOut {
    return volume_direct(in, false);
}

// Where the count is not 0.
@fragment
fn fs_volume_shadowed(in: MainOut) -> VolumeOut {
    return volume_direct(in, true);
}

@fragment
fn fs_volume_lit_frag_depth(in: MainOut) -> VolumeDepthOut {
    return with_depth(volume_direct(in, false), in);
}

@fragment
fn fs_volume_shadowed_frag_depth(in: MainOut) -> VolumeDepthOut {
    return with_depth(volume_direct(in, true), in);
}

struct VolumeVertex {
    @builtin(position) clip: vec4<f32>,
    @location(0) depth: vec2<f32>,
};

// How far vs_volume moves its depth, in units of the f32's last place of each fragment's
// depth: positive behind (reversed Z: toward 0; the volumes' caps), negative in front (the
// planar receiver). z scaled at the vertices scales z / w, and so the depth, everywhere.
override DEPTH_PUSH_ULPS: f32 = 0.0;

// Volume geometry: homogeneous view-space positions (w = 0 at infinity) through the
// infinite projection; stencil only.
@vertex
fn vs_volume(@location(0) position: vec4<f32>) -> VolumeVertex {
    var out: VolumeVertex;
    out.clip = frame.infinite_clip_from_camera * position;
    out.clip.z = out.clip.z * (1.0 - DEPTH_PUSH_ULPS * 1.1920929e-7);
    out.depth = out.clip.zw;
    return out;
}

// The volumes' depth from the fragment shader (GL; see MainOut.depth), pushed behind as the
// volume pipelines' depth bias does elsewhere (which does not apply to a written depth):
// 0.05 of the slope (vs_volume's DEPTH_PUSH_ULPS is in the depth already).
@fragment
fn fs_volume_frag_depth(in: VolumeVertex) -> @builtin(frag_depth) f32 {
    let d = in.depth.x / in.depth.y;
    let slope = max(abs(dpdx(d)), abs(dpdy(d)));
    return max(d - 0.05 * slope, 0.0);
}

// Planar shadows' receiver polygon from the fragment shader (GL), pulled in front of the
// receiver's own face it lies on (the planar pipelines' depth bias elsewhere): 0.05 of the
// slope (vs_volume's DEPTH_PUSH_ULPS is in the depth already).
@fragment
fn fs_planar_frag_depth(in: VolumeVertex) -> @builtin(frag_depth) f32 {
    let d = in.depth.x / in.depth.y;
    let slope = max(abs(dpdx(d)), abs(dpdy(d)));
    return min(d + 0.05 * slope, 1.0);
}

struct FullscreenOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) uv: vec2<f32>,
};

@vertex
fn vs_fullscreen(@builtin(vertex_index) i: u32) -> FullscreenOut {
    let uv = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    var out: FullscreenOut;
    out.clip = vec4<f32>(uv * vec2<f32>(2.0, -2.0) + vec2<f32>(-1.0, 1.0), 0.0, 1.0);
    out.uv = uv;
    return out;
}

// Map `slot.map` as the light sees it: near dark, far light.
@fragment
fn fs_light_view(in: FullscreenOut) -> @location(0) vec4<f32> {
    let m = gnomon_shadows.maps[slot.map];
    let d = textureSampleLevel(
        gnomon_raw, gnomon_nearest, m.rect.xy + in.uv * m.rect.zw, i32(m.info.x), 0.0).r;
    let v = (40.0 + 215.0 * clamp(d, 0.0, 1.0)) / 255.0;
    return vec4<f32>(v, v, v, 1.0);
}

// The view samples pass: per pixel, the camera-relative position and the geometric normal
// (turned toward the camera) as the bits of f32, w = 1 where there is geometry.
struct SamplesOut {
    @location(0) position: vec4<u32>,
    @location(1) normal: vec4<u32>,
};

fn view_samples(in: MainOut) -> SamplesOut {
    let s = surface(in, dpdx(in.camera), dpdy(in.camera));
    return SamplesOut(
        bitcast<vec4<u32>>(vec4<f32>(s.p, 1.0)),
        bitcast<vec4<u32>>(vec4<f32>(s.n_geo, 1.0)),
    );
}

@fragment
fn fs_samples(in: MainOut) -> SamplesOut {
    return view_samples(in);
}

struct SamplesDepthOut {
    @location(0) position: vec4<u32>,
    @location(1) normal: vec4<u32>,
    @builtin(frag_depth) depth: f32,
};

@fragment
fn fs_samples_frag_depth(in: MainOut) -> SamplesDepthOut {
    let s = view_samples(in);
    return SamplesDepthOut(s.position, s.normal, in.depth.x / in.depth.y);
}

// Probes: light 0's one-tap shadow state at given surface points (view space), one point per
// texel of a PROBE_SIZE x PROBE_SIZE R32Uint target, in order. Bit 0: lit by the map (as the
// main pass's mask reads it: the selected map, beyond the shadow distance lit); bit 1: probed.
const PROBE_SIZE: u32 = 256u;

struct ProbeOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) camera: vec3<f32>,
    @location(1) normal: vec3<f32>,
};

@vertex
fn vs_probe(@location(0) position: vec3<f32>, @location(1) normal: vec3<f32>, @builtin(vertex_index) index: u32) -> ProbeOut {
    let x = f32(index % PROBE_SIZE);
    let y = f32(index / PROBE_SIZE);
    var out: ProbeOut;
    out.clip = vec4<f32>(
        (2.0 * x + 1.0) / f32(PROBE_SIZE) - 1.0,
        1.0 - (2.0 * y + 1.0) / f32(PROBE_SIZE),
        0.5,
        1.0,
    );
    out.camera = position;
    out.normal = normal;
    return out;
}

@fragment
fn fs_probe(in: ProbeOut) -> @location(0) vec4<u32> {
    let p = in.camera;
    var n = normalize(in.normal);
    if (dot(n, -p) < 0.0) {
        n = -n;
    }
    let incidence = gnomon_incidence(0u, p);
    let n_dot_l = dot(n, incidence.to_light);
    let selected = gnomon_select(0u, p);
    var lit = 1u;
    if (selected.fade < 1.0) {
        let read = gnomon_read_surface(0u, selected.map, p, n, n_dot_l, GNOMON_FILTER_ONE_TAP);
        lit = select(0u, 1u, read > 0.5);
    }
    return vec4<u32>(lit | 2u, 0u, 0u, 0u);
}

// gnomon's shadow lookup: the per-map and per-light records and the functions that read them.
//
// Shipped for engines that keep their own main pass: `gnomon_render::lookup_wgsl(group)` gives
// this module with its bindings in bind group `group`; bind `Renderer::shadow_bind_group()`
// there. Positions and directions are in the camera's view space (gnomon's
// `Camera::view_from_world`: right-handed, +Y up, looking down -Z), so that the matrices stay
// small wherever the scene is; compute view-space positions from your own `view_from_object`
// in f64 on the CPU.
//
// A map's clip space: x, y in [-1, 1] over the whole map, +y up (texture v = 0.5 - 0.5 y);
// depth compared is linear along the light (`depth_from_camera`), 0 near and 1 far, stored
// with the bias already added by gnomon's depth pass; a point behind a perspective map
// (w <= 0) or outside it reads as lit.

const GNOMON_MAX_LIGHTS: u32 = 4u;
const GNOMON_MAX_MAPS: u32 = 48u;

// GnomonLight.info.x: the light's kind.
const GNOMON_LIGHT_DIRECTIONAL: u32 = 0u;
const GNOMON_LIGHT_SPOT: u32 = 1u;
const GNOMON_LIGHT_POINT: u32 = 2u;
// GnomonLight.info.y: how a point picks one of the light's maps.
const GNOMON_SELECT_SINGLE: u32 = 0u;
// params[0] is a plane (view space): points on its positive side read the second map (SPPSM).
const GNOMON_SELECT_PLANE: u32 = 1u;
// Cascades: params[0].x to params[2].x hold the view depths z_0 ..= z_K (K = the number of
// maps; map i covers z_i to z_i+1), params[2].y the blend band as a fraction of a slice,
// params[2].z where shadows begin to fade (nothing is shadowed beyond z_K), params[3] the
// view-depth row (view space).
const GNOMON_SELECT_CASCADES: u32 = 2u;
// A point light's cube: params[0..3].xyz the world axes x, y, z (view space), the map of face
// k (+x, -x, +y, -y, +z, -z) relative to the first, or -1 where the face has none: faces 0 to
// 2 in params[0..3].w, 3 to 5 in params[3].xyz. A point reads the face of its direction's
// major world axis; a face without a map reads as lit.
const GNOMON_SELECT_CUBE: u32 = 3u;
// Stable cascades picked by coverage (gnomon::CascadeSlices::covers): the cascades'
// parameters, and a point reads the first map up to its view depth's slice's whose square
// (less GNOMON_COVER_MARGIN_TEXELS) holds it; the blend band is then the outer `blend`
// fraction of that square, toward the next map where it holds the point.
const GNOMON_SELECT_CASCADES_BY_COVER: u32 = 4u;
const GNOMON_COVER_MARGIN_TEXELS: f32 = 4.0;
// GnomonShadows.info.y: the filter.
const GNOMON_FILTER_ONE_TAP: u32 = 0u;
const GNOMON_FILTER_HARDWARE_2X2: u32 = 1u;
const GNOMON_FILTER_PCF_5X5: u32 = 2u;
// Percentage-closer soft shadows (Fernando 2005) of each light's area (GnomonLight.range.z):
// a blocker search, the penumbra's width from the blockers' distance, then a filter that wide;
// both footprints are discs across the light's rays carried into the map by its local
// Jacobian, so that they are right on warped maps and cascades too.
const GNOMON_FILTER_PCSS: u32 = 3u;
// PCSS's taps (Vogel's spiral over the disc) and the largest radius of the blocker search's
// and the filter's footprints, in texels (a wider search averages blockers that do not hide
// the light: over compare's demo views with a 2-degree sun, a search of 24 to 48 texels
// measured best, 96 or 256 worse).
const GNOMON_PCSS_SEARCH_TAPS: i32 = 16;
const GNOMON_PCSS_FILTER_TAPS: i32 = 32;
const GNOMON_PCSS_MAX_SEARCH_TEXELS: f32 = 32.0;
const GNOMON_PCSS_MAX_FILTER_TEXELS: f32 = 128.0;
// How a main pass reads the maps (gnomon's passes: the override constant MAP_READ).
// By depth: shadowed where a caster nearer the light than the point is stored.
const GNOMON_READ_DEPTH: u32 = 0u;
// Object IDs (the shadows lecture's "Object ID Shadows"): the ID map holds the ID of the
// object nearest the light per texel; a point is shadowed where it finds another object's,
// lit where it finds its own or none. No bias; an object cannot shadow itself.
const GNOMON_READ_OBJECT_ID: u32 = 1u;
// IDs and depth (the lecture's "Combining Shadow and Object Maps"): another object's ID
// shadows; where the texel holds the point's own object, its depth decides (self-shadowing).
const GNOMON_READ_ID_DEPTH: u32 = 2u;
// GnomonMap.info.y: flags.
const GNOMON_MAP_PERSPECTIVE: u32 = 1u;
// One hemisphere of a dual paraboloid map: clip_from_camera takes a point to q, the
// hemisphere's frame in units of the light's range; it lands at
// GNOMON_PARABOLOID_SCALE q.xy / (|q| + q.z) (inset), compared at depth |q|; the hemisphere
// reaches GNOMON_PARABOLOID_RIM (-sin of gnomon::PARABOLOID_MARGIN_DEGREES) past 90 degrees.
const GNOMON_MAP_PARABOLOID: u32 = 2u;
const GNOMON_PARABOLOID_SCALE: f32 = 0.94896456671488;
const GNOMON_PARABOLOID_RIM: f32 = -0.05233595624294383;

// A paraboloid map's scale from q.xy / (|q| + q.z) into its inset square (`info`: its
// GnomonMap.info, resolution and inset in z and w).
fn gnomon_paraboloid_scale(info: vec4<u32>) -> f32 {
    return GNOMON_PARABOLOID_SCALE * (1.0 - 2.0 * f32(info.w) / f32(info.z));
}

struct GnomonMap {
    // View space to the map's clip space.
    clip_from_camera: mat4x4<f32>,
    // View space to the compared depth (linear along the light).
    depth_from_camera: vec4<f32>,
    // xy: the map's corner in its layer (texture coordinates), zw: its size there.
    rect: vec4<f32>,
    // x: constant bias (depth units), y: slope scale (texels), z: largest slope bias (depth
    // units), w: normal offset (texels).
    bias: vec4<f32>,
    // x: the largest slope bias in texel widths across the light, where that exceeds bias.z
    // (0: bias.z alone; a paraboloid map's texel measured across its own ray); yzw: unused.
    slope_cap: vec4<f32>,
    // x: array layer, y: flags, z: resolution (texels), w: inset (texels).
    info: vec4<u32>,
};

struct GnomonLight {
    // xyz: the direction the light travels (directional) or its position (spot, point), view
    // space.
    vector: vec4<f32>,
    // xyz: the spot's axis, w: cos of its half-angle.
    spot: vec4<f32>,
    // x: the spot's or point light's range, y: its near distance, z: its area's size for
    // soft shadows (directional: the tangent of its angular radius; spot and point: its
    // radius in world units).
    range: vec4<f32>,
    // x: kind, y: selection, z: first map, w: number of maps.
    info: vec4<u32>,
    // The selection's parameters (see GNOMON_SELECT_*).
    params: array<vec4<f32>, 4>,
};

struct GnomonShadows {
    lights: array<GnomonLight, GNOMON_MAX_LIGHTS>,
    maps: array<GnomonMap, GNOMON_MAX_MAPS>,
    // x: number of lights, y: filter.
    info: vec4<u32>,
};

@group(GNOMON_GROUP) @binding(0) var<uniform> gnomon_shadows: GnomonShadows;
// The maps, one array layer each, bound twice: for comparison sampling and for raw reads
// (one sampler per texture, as GLSL needs).
@group(GNOMON_GROUP) @binding(1) var gnomon_depth: texture_depth_2d_array;
@group(GNOMON_GROUP) @binding(2) var gnomon_compare: sampler_comparison;
@group(GNOMON_GROUP) @binding(3) var gnomon_raw: texture_2d_array<f32>;
@group(GNOMON_GROUP) @binding(4) var gnomon_nearest: sampler;
// The object-ID maps, one layer per map beside its depth (0: no caster drawn there, else the
// caster's ID: gnomon's depth pass writes its draw's instance index + 1).
@group(GNOMON_GROUP) @binding(5) var gnomon_ids: texture_2d_array<u32>;

// Cascade view depth z_i of the depths z_0..z_3 (z_a), z_4..z_7 (z_b) and z_8, picked by
// comparing indices.
fn gnomon_pick_depth(z_a: vec4<f32>, z_b: vec4<f32>, z_8: f32, i: u32) -> f32 {
    let ones = vec4<f32>(1.0);
    let a = dot(select(vec4<f32>(0.0), z_a, vec4<u32>(0u, 1u, 2u, 3u) == vec4<u32>(i)), ones);
    let b = dot(select(vec4<f32>(0.0), z_b, vec4<u32>(4u, 5u, 6u, 7u) == vec4<u32>(i)), ones);
    return select(a + b, z_8, i == 8u);
}

// How a point reads `light`'s maps: `map` (an index into the maps), the weight of the next
// map in a cascade's blend band, and how far shadows have faded (1: nothing shadowed).
struct GnomonSelection {
    map: u32,
    next_weight: f32,
    fade: f32,
};

// The map of a point light's cube face that the direction from the light to p falls in,
// relative to the light's first map; -1 where that face has none.
fn gnomon_cube_face_map(light: u32, p: vec3<f32>) -> i32 {
    let axes_0 = gnomon_shadows.lights[light].params[0];
    let axes_1 = gnomon_shadows.lights[light].params[1];
    let axes_2 = gnomon_shadows.lights[light].params[2];
    let rest = gnomon_shadows.lights[light].params[3];
    let d = p - gnomon_shadows.lights[light].vector.xyz;
    let w = vec3<f32>(dot(d, axes_0.xyz), dot(d, axes_1.xyz), dot(d, axes_2.xyz));
    let a = abs(w);
    // The major axis, the first of x, y, z on a tie (as gnomon::PointLight::face_of).
    var map = select(rest.z, rest.y, w.z >= 0.0);
    if (a.x >= a.y && a.x >= a.z) {
        map = select(axes_1.w, axes_0.w, w.x >= 0.0);
    } else if (a.y >= a.z) {
        map = select(rest.x, axes_2.w, w.y >= 0.0);
    }
    return i32(round(map));
}

fn gnomon_select(light: u32, p: vec3<f32>) -> GnomonSelection {
    let info = gnomon_shadows.lights[light].info;
    let count = max(info.w, 1u);
    var out = GnomonSelection(info.z, 0.0, 0.0);
    if (info.y == GNOMON_SELECT_CUBE) {
        let k = gnomon_cube_face_map(light, p);
        out.map = info.z + u32(max(k, 0));
        // A face without a map: nothing there is shadowed.
        out.fade = select(0.0, 1.0, k < 0);
    } else if (info.y != GNOMON_SELECT_CASCADES && info.y != GNOMON_SELECT_CASCADES_BY_COVER) {
        out.map = gnomon_plane_map_index(light, p);
    } else {
        // Without indexing by a computed value (a gather per fragment on a CPU rasteriser):
        // z_0..z_3, z_4..z_7 and z_8 as vectors, their indices beside them.
        let z_a = gnomon_shadows.lights[light].params[0];
        let z_b = gnomon_shadows.lights[light].params[1];
        let extra = gnomon_shadows.lights[light].params[2];
        let depth = dot(gnomon_shadows.lights[light].params[3], vec4<f32>(p, 1.0));
        let i_a = vec4<u32>(0u, 1u, 2u, 3u);
        let i_b = vec4<u32>(4u, 5u, 6u, 7u);
        let d = vec4<f32>(depth);
        // k: the inner boundaries z_1 .. z_(K-1) passed.
        let passed_a = (d >= z_a) & (i_a >= vec4<u32>(1u)) & (i_a < vec4<u32>(count));
        let passed_b = (d >= z_b) & (i_b < vec4<u32>(count));
        let ones = vec4<u32>(1u);
        let zeros = vec4<u32>(0u);
        let k = dot(select(zeros, ones, passed_a), ones) + dot(select(zeros, ones, passed_b), ones);
        out.map = info.z + k;
        let z0 = gnomon_pick_depth(z_a, z_b, extra.x, k);
        let z1 = gnomon_pick_depth(z_a, z_b, extra.x, k + 1u);
        let end = gnomon_pick_depth(z_a, z_b, extra.x, count);
        let band = extra.y * (z1 - z0);
        if (k + 1u < count && band > 0.0) {
            out.next_weight = clamp((depth - (z1 - band)) / band, 0.0, 1.0);
        }
        if (info.y == GNOMON_SELECT_CASCADES_BY_COVER) {
            // The first map before k's that holds p, with how far out in its square p lies
            // (1: at the held square's edge).
            for (var j = 0u; j < k; j++) {
                let r = gnomon_cover_extent(info.z + j, p);
                if (r <= 1.0) {
                    out.map = info.z + j;
                    let blend = extra.y;
                    // The next map's square is read only where there is a band.
                    let blends = blend > 0.0 && (j + 1u == k || gnomon_cover_extent(info.z + j + 1u, p) <= 1.0);
                    out.next_weight = select(0.0, clamp((r - (1.0 - blend)) / blend, 0.0, 1.0), blends);
                    break;
                }
            }
        }
        let fade_start = extra.z;
        if (depth >= end) {
            out.fade = 1.0;
        } else if (end > fade_start) {
            out.fade = clamp((depth - fade_start) / (end - fade_start), 0.0, 1.0);
        }
    }
    return out;
}

// How far out in map `map`'s square point p lies: the larger of its |clip x| and |clip y|
// over the held square's (the inset square less GNOMON_COVER_MARGIN_TEXELS texels); at most 1
// where the map holds p.
fn gnomon_cover_extent(map: u32, p: vec3<f32>) -> f32 {
    let c = gnomon_shadows.maps[map].clip_from_camera * vec4<f32>(p, 1.0);
    let info = gnomon_shadows.maps[map].info;
    let limit = 1.0 - 2.0 * (f32(info.w) + GNOMON_COVER_MARGIN_TEXELS) / f32(info.z);
    return max(abs(c.x), abs(c.y)) / limit;
}

// The map of `light` that point `p` reads for the single and plane selections (without the
// cascades' code, which costs a CPU rasteriser even where it does not run).
fn gnomon_plane_map_index(light: u32, p: vec3<f32>) -> u32 {
    let info = gnomon_shadows.lights[light].info;
    var k = 0u;
    if (info.y == GNOMON_SELECT_PLANE) {
        let plane = gnomon_shadows.lights[light].params[0];
        k = select(0u, 1u, dot(plane.xyz, p) + plane.w > 0.0);
    }
    return info.z + min(k, max(info.w, 1u) - 1u);
}

// The map of `light` that point `p` reads, any selection (in a cascade's blend band, the
// nearer one; for a cube face without a map, the first).
fn gnomon_map_index(light: u32, p: vec3<f32>) -> u32 {
    let selection = gnomon_shadows.lights[light].info.y;
    if (selection == GNOMON_SELECT_CASCADES || selection == GNOMON_SELECT_CASCADES_BY_COVER
        || selection == GNOMON_SELECT_CUBE) {
        return gnomon_select(light, p).map;
    }
    return gnomon_plane_map_index(light, p);
}

struct GnomonIncidence {
    // Unit vector from the point toward the light.
    to_light: vec3<f32>,
    // Inside the spot's cone and range (always for a directional light).
    in_light: bool,
    // The cone's soft edge, 0 to 1.
    cone: f32,
};

// (Fields are read one by one, not as whole records: copying a record loads all of it.)
fn gnomon_incidence(light: u32, p: vec3<f32>) -> GnomonIncidence {
    let vector = gnomon_shadows.lights[light].vector;
    var out: GnomonIncidence;
    if (gnomon_shadows.lights[light].info.x == GNOMON_LIGHT_DIRECTIONAL) {
        out.to_light = -vector.xyz;
        out.in_light = true;
        out.cone = 1.0;
        return out;
    }
    let range = gnomon_shadows.lights[light].range;
    let d = vector.xyz - p;
    if (gnomon_shadows.lights[light].info.x == GNOMON_LIGHT_POINT) {
        let distance = length(d);
        out.to_light = d / distance;
        out.in_light = distance <= range.x && distance >= range.y;
        out.cone = 1.0;
        return out;
    }
    let spot = gnomon_shadows.lights[light].spot;
    out.to_light = normalize(d);
    let along = dot(-d, spot.xyz);
    let cos_angle = dot(-out.to_light, spot.xyz);
    out.in_light = cos_angle >= spot.w && along <= range.x && along >= range.y;
    out.cone = smoothstep(spot.w, min(spot.w + 0.03, 1.0), cos_angle);
    return out;
}

// What a lookup needs of one map, read from its record once (each read of a record indexed
// per fragment is a gather on a CPU rasteriser).
struct GnomonMapView {
    clip_from_camera: mat4x4<f32>,
    depth_from_camera: vec4<f32>,
    rect: vec4<f32>,
    layer: i32,
    resolution: f32,
    normal_offset: f32,
    // The constant depth bias (depth units).
    constant_bias: f32,
    // A paraboloid hemisphere, and its scale into the inset square.
    paraboloid: bool,
    paraboloid_scale: f32,
};

fn gnomon_map_view(map: u32) -> GnomonMapView {
    let info = gnomon_shadows.maps[map].info;
    return GnomonMapView(
        gnomon_shadows.maps[map].clip_from_camera,
        gnomon_shadows.maps[map].depth_from_camera,
        gnomon_shadows.maps[map].rect,
        i32(info.x),
        f32(info.z),
        gnomon_shadows.maps[map].bias.w,
        gnomon_shadows.maps[map].bias.x,
        (info.y & GNOMON_MAP_PARABOLOID) != 0u,
        gnomon_paraboloid_scale(info),
    );
}

// The gradients of the map's normalised x and y at p (per view-space unit):
// (row_i - ndc_i row_w) / w, exact for any projective map. Zero behind the map.
fn gnomon_ndc_gradients(view: GnomonMapView, p: vec3<f32>) -> mat2x3<f32> {
    let m = view.clip_from_camera;
    let row_0 = vec3<f32>(m[0][0], m[1][0], m[2][0]);
    let row_1 = vec3<f32>(m[0][1], m[1][1], m[2][1]);
    let row_2 = vec3<f32>(m[0][2], m[1][2], m[2][2]);
    if (view.paraboloid) {
        // f = k q.xy / s with s = |q| + q.z: df/dq = k (e / s - q.xy (q / |q| + e_z) / s^2),
        // then through q's rows.
        let q = (m * vec4<f32>(p, 1.0)).xyz;
        let d = length(q);
        let s = d + q.z;
        if (d <= 0.0 || s <= 0.0) {
            return mat2x3<f32>(vec3<f32>(0.0), vec3<f32>(0.0));
        }
        let k = view.paraboloid_scale;
        let g = q / d + vec3<f32>(0.0, 0.0, 1.0);
        let dfx = k * (vec3<f32>(1.0, 0.0, 0.0) / s - (q.x / (s * s)) * g);
        let dfy = k * (vec3<f32>(0.0, 1.0, 0.0) / s - (q.y / (s * s)) * g);
        return mat2x3<f32>(
            dfx.x * row_0 + dfx.y * row_1 + dfx.z * row_2,
            dfy.x * row_0 + dfy.y * row_1 + dfy.z * row_2,
        );
    }
    let clip = m * vec4<f32>(p, 1.0);
    if (clip.w <= 0.0) {
        return mat2x3<f32>(vec3<f32>(0.0), vec3<f32>(0.0));
    }
    let row_x = vec3<f32>(m[0][0], m[1][0], m[2][0]);
    let row_y = vec3<f32>(m[0][1], m[1][1], m[2][1]);
    let row_w = vec3<f32>(m[0][3], m[1][3], m[2][3]);
    return mat2x3<f32>(
        (row_x - (clip.x / clip.w) * row_w) / clip.w,
        (row_y - (clip.y / clip.w) * row_w) / clip.w,
    );
}

// The world size of the map's largest texel side at p (warps stretch texels differently
// along x and y).
fn gnomon_texel_world_size(view: GnomonMapView, p: vec3<f32>) -> f32 {
    let g = gnomon_ndc_gradients(view, p);
    return (2.0 / view.resolution) / max(min(length(g[0]), length(g[1])), 1e-30);
}

// The map's texture coordinate `uv` kept on its own texels, in its layer's coordinates.
fn gnomon_layer_uv(view: GnomonMapView, uv: vec2<f32>) -> vec2<f32> {
    let half_texel = 0.5 / view.resolution;
    return view.rect.xy + clamp(uv, vec2<f32>(half_texel), vec2<f32>(1.0 - half_texel)) * view.rect.zw;
}

// One raw tap at the map's texture coordinate `uv`: 1 where `reference` is not farther than
// the stored depth.
fn gnomon_tap(view: GnomonMapView, uv: vec2<f32>, reference: f32) -> f32 {
    let stored = textureSampleLevel(
        gnomon_raw, gnomon_nearest, gnomon_layer_uv(view, uv), view.layer, 0.0).r;
    return select(0.0, 1.0, reference <= stored);
}

// 1 where p is lit according to the map, 0 where shadowed, between for filtered lookups.
// Where p lands in a map (normalised x, y), the depth it is compared at, and whether the map
// holds it (in front of a perspective map, inside a paraboloid hemisphere's rim).
struct GnomonMapPoint {
    ndc: vec2<f32>,
    reference: f32,
    inside: bool,
};

fn gnomon_map_point(view: GnomonMapView, p: vec3<f32>) -> GnomonMapPoint {
    var out: GnomonMapPoint;
    let clip = view.clip_from_camera * vec4<f32>(p, 1.0);
    if (view.paraboloid) {
        let q = clip.xyz;
        let d = length(q);
        out.inside = d > 0.0 && q.z >= GNOMON_PARABOLOID_RIM * d;
        out.ndc = q.xy * (view.paraboloid_scale / max(d + q.z, 1e-30));
        out.reference = d;
        return out;
    }
    out.inside = clip.w > 0.0;
    out.ndc = clip.xy / clip.w;
    out.reference = dot(view.depth_from_camera, vec4<f32>(p, 1.0));
    return out;
}

// The map's texture coordinates of a point's normalised x and y.
fn gnomon_uv(ndc: vec2<f32>) -> vec2<f32> {
    return vec2<f32>(0.5 + 0.5 * ndc.x, 0.5 - 0.5 * ndc.y);
}

fn gnomon_lookup_view(view: GnomonMapView, p: vec3<f32>, filter_mode: u32) -> f32 {
    let at = gnomon_map_point(view, p);
    if (!at.inside) {
        return 1.0;
    }
    let uv = gnomon_uv(at.ndc);
    let reference = at.reference;
    if (filter_mode == GNOMON_FILTER_HARDWARE_2X2) {
        return textureSampleCompareLevel(
            gnomon_depth, gnomon_compare, gnomon_layer_uv(view, uv), view.layer, reference);
    }
    if (filter_mode == GNOMON_FILTER_PCF_5X5) {
        let texel = 1.0 / view.resolution;
        var sum = 0.0;
        for (var y = -2; y <= 2; y++) {
            for (var x = -2; x <= 2; x++) {
                sum += gnomon_tap(view, uv + vec2<f32>(f32(x), f32(y)) * texel, reference);
            }
        }
        return sum / 25.0;
    }
    return gnomon_tap(view, uv, reference);
}

// Whether the one-tap lookup of `view` at p is sure to be right. The 3x3 texels around the
// one it reads must give the same answer, each with its stored depth clear of p's: within the
// constant bias nearer the light, or half of it farther, a caster or the surface itself lies
// where acne and peter-panning live. Outside the map, or within a texel and a half of its
// border, the lookup reads the border's texels (clamped): it is sure only where they hold
// nothing that reaches p, since a map's setup holds every caster over its receivers.
fn gnomon_lookup_sure(view: GnomonMapView, p: vec3<f32>) -> bool {
    let at = gnomon_map_point(view, p);
    if (!at.inside) {
        return false;
    }
    let uv = gnomon_uv(at.ndc);
    let texel = 1.0 / view.resolution;
    let inner = clamp(uv, vec2<f32>(1.5 * texel), vec2<f32>(1.0 - 1.5 * texel));
    let near_border = any(inner != uv);
    var lit = 0;
    for (var y = -1; y <= 1; y++) {
        for (var x = -1; x <= 1; x++) {
            let stored = textureSampleLevel(
                gnomon_raw, gnomon_nearest,
                gnomon_layer_uv(view, inner + vec2<f32>(f32(x), f32(y)) * texel), view.layer, 0.0).r;
            let margin = stored - at.reference;
            if (margin > -view.constant_bias && margin < 0.5 * view.constant_bias) {
                return false;
            }
            lit += select(0, 1, margin >= 0.0);
        }
    }
    return lit == 9 || (lit == 0 && !near_border);
}

// One texel of the object-ID map read by the object `object` at `reference` (`texel`: the
// texel's integer coordinates in the map, clamped to it): 1 lit, 0 shadowed.
fn gnomon_id_tap(view: GnomonMapView, texel: vec2<f32>, object: u32, reference: f32, read: u32) -> f32 {
    let t = clamp(texel, vec2<f32>(0.0), vec2<f32>(view.resolution - 1.0));
    let layer_size = vec2<f32>(textureDimensions(gnomon_ids).xy);
    let found = textureLoad(gnomon_ids, vec2<i32>(view.rect.xy * layer_size + t), view.layer, 0).r;
    if (found == 0u) {
        return 1.0;
    }
    if (found != object) {
        return 0.0;
    }
    if (read == GNOMON_READ_OBJECT_ID) {
        return 1.0;
    }
    // The object's own texel: its depth, read at the texel's centre.
    let uv = view.rect.xy + (t + 0.5) / view.resolution * view.rect.zw;
    let stored = textureSampleLevel(gnomon_raw, gnomon_nearest, uv, view.layer, 0.0).r;
    return select(0.0, 1.0, reference <= stored);
}

// The object-ID map of `view` read at p by the object `object` (GNOMON_READ_OBJECT_ID or
// GNOMON_READ_ID_DEPTH): 1 lit, 0 shadowed; the filters weigh the texels' verdicts as they
// weigh depth comparisons (2x2: bilinear, 5x5: the mean).
fn gnomon_lookup_ids(view: GnomonMapView, p: vec3<f32>, object: u32, read: u32, filter_mode: u32) -> f32 {
    let at = gnomon_map_point(view, p);
    if (!at.inside) {
        return 1.0;
    }
    let uv = gnomon_uv(at.ndc);
    // Texel centres at whole numbers.
    let texel = uv * view.resolution - 0.5;
    if (filter_mode == GNOMON_FILTER_HARDWARE_2X2) {
        let base = floor(texel);
        let f = texel - base;
        let top = mix(
            gnomon_id_tap(view, base, object, at.reference, read),
            gnomon_id_tap(view, base + vec2<f32>(1.0, 0.0), object, at.reference, read),
            f.x);
        let bottom = mix(
            gnomon_id_tap(view, base + vec2<f32>(0.0, 1.0), object, at.reference, read),
            gnomon_id_tap(view, base + vec2<f32>(1.0, 1.0), object, at.reference, read),
            f.x);
        return mix(top, bottom, f.y);
    }
    let centre = round(texel);
    if (filter_mode == GNOMON_FILTER_PCF_5X5) {
        var sum = 0.0;
        for (var y = -2; y <= 2; y++) {
            for (var x = -2; x <= 2; x++) {
                sum += gnomon_id_tap(view, centre + vec2<f32>(f32(x), f32(y)), object, at.reference, read);
            }
        }
        return sum / 25.0;
    }
    return gnomon_id_tap(view, centre, object, at.reference, read);
}

// gnomon_lookup_view of map `map`.
fn gnomon_lookup(map: u32, p: vec3<f32>, filter_mode: u32) -> f32 {
    return gnomon_lookup_view(gnomon_map_view(map), p, filter_mode);
}

// The point where a map is read for a surface point p with geometric normal n_geo (unit,
// toward the viewer) and n_dot_l = dot(n_geo, to_light): moved along the normal by the
// map's normal offset in texels, more where the light grazes the surface.
//
// A texel here is measured along the normal's own image in the map: the step along n_geo
// that moves the lookup one texel (at most the texel's largest side). That is the step a
// surface needs: a plane receding from the light at a grazing angle changes depth across a
// texel along that image, and moving one texel off it clears that. The largest side alone
// moved the lookup several texels along a map's fine axis (a low sun's map is fine along the
// world's up), so the ground nearest a cascade's camera, at the edge of its map, was read
// in the cleared border as lit (random scene 227: 3.8% of the pixels missed their shadow).
fn gnomon_offset_point(view: GnomonMapView, p: vec3<f32>, n_geo: vec3<f32>, n_dot_l: f32) -> vec3<f32> {
    let g = gnomon_ndc_gradients(view, p);
    let finest = min(length(g[0]), length(g[1]));
    let along_normal = length(vec2<f32>(dot(g[0], n_geo), dot(g[1], n_geo)));
    let size = (2.0 / view.resolution) / max(max(finest, along_normal), 1e-30);
    return p + n_geo * view.normal_offset * size * clamp(1.0 - n_dot_l, 0.0, 1.0);
}

// Where `light`'s map `map` is read for the surface point p: the map's view and the point
// moved by its normal offset. For a point light's cube the face is picked again at the moved
// point (the offset can cross a face's border); `covered` is false where that face has no
// map (the point reads as lit).
struct GnomonReadAt {
    view: GnomonMapView,
    point: vec3<f32>,
    covered: bool,
};

fn gnomon_read_at(light: u32, map: u32, p: vec3<f32>, n_geo: vec3<f32>, n_dot_l: f32) -> GnomonReadAt {
    var out: GnomonReadAt;
    out.view = gnomon_map_view(map);
    out.point = gnomon_offset_point(out.view, p, n_geo, n_dot_l);
    out.covered = true;
    if (gnomon_shadows.lights[light].info.y == GNOMON_SELECT_CUBE) {
        let k = gnomon_cube_face_map(light, out.point);
        out.covered = k >= 0;
        let again = gnomon_shadows.lights[light].info.z + u32(max(k, 0));
        if (again != map) {
            out.view = gnomon_map_view(again);
        }
    }
    return out;
}

// `light`'s map `map` read at the surface point p (see gnomon_read_at).
fn gnomon_read_surface(light: u32, map: u32, p: vec3<f32>, n_geo: vec3<f32>, n_dot_l: f32, filter_mode: u32) -> f32 {
    let at = gnomon_read_at(light, map, p, n_geo, n_dot_l);
    if (!at.covered) {
        return 1.0;
    }
    if (filter_mode == GNOMON_FILTER_PCSS) {
        return gnomon_lookup_pcss(light, at.view, at.point, n_geo);
    }
    return gnomon_lookup_view(at.view, at.point, filter_mode);
}

// The change of a map's compared depth per world unit along `direction` at p.
fn gnomon_depth_rate(view: GnomonMapView, p: vec3<f32>, direction: vec3<f32>) -> f32 {
    if (view.paraboloid) {
        // depth = |q|, q = the hemisphere's frame: d|q| = (q / |q|) . dq.
        let m = view.clip_from_camera;
        let q = (m * vec4<f32>(p, 1.0)).xyz;
        let dq = (m * vec4<f32>(direction, 0.0)).xyz;
        return dot(q, dq) / max(length(q), 1e-30);
    }
    return dot(view.depth_from_camera.xyz, direction);
}

// A unit vector perpendicular to the unit vector n.
fn gnomon_perpendicular(n: vec3<f32>) -> vec3<f32> {
    let axis = select(vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(0.0, 1.0, 0.0), abs(n.x) > 0.7);
    return normalize(cross(n, axis));
}

// Point on Vogel's spiral over the unit disc: tap i of n.
fn gnomon_vogel(i: i32, n: i32) -> vec2<f32> {
    let r = sqrt((f32(i) + 0.5) / f32(n));
    let phi = f32(i) * 2.39996323;
    return r * vec2<f32>(cos(phi), sin(phi));
}

// Percentage-closer soft shadows of `light`'s area at the surface point p (geometric normal
// n_geo) in map `view`: 1 lit, 0 in the umbra. The footprints are discs across the light's
// rays at p, carried into the map's normalised coordinates by its Jacobian there (so their
// size is right on warped maps), and compared against the receiver's own plane (its depth
// at each tap from the Jacobian: receiver-plane depth bias), so that wide filters do not
// shadow the surface by itself.
fn gnomon_lookup_pcss(light: u32, view: GnomonMapView, p: vec3<f32>, n_geo: vec3<f32>) -> f32 {
    let at = gnomon_map_point(view, p);
    if (!at.inside) {
        return 1.0;
    }
    let kind = gnomon_shadows.lights[light].info.x;
    let area = gnomon_shadows.lights[light].range.z;
    let to_light = gnomon_incidence(light, p).to_light;
    // The distance to a spot or point light (unused for a directional one).
    let distance = length(gnomon_shadows.lights[light].vector.xyz - p);
    // Across the light's rays: u, v; the map's normalised coordinates per world unit along
    // them (columns of jacobian).
    let g = gnomon_ndc_gradients(view, p);
    let u = gnomon_perpendicular(to_light);
    let v = cross(to_light, u);
    let jacobian = mat2x2<f32>(vec2<f32>(dot(g[0], u), dot(g[1], u)), vec2<f32>(dot(g[0], v), dot(g[1], v)));
    // Depth units per world unit toward the light (positive: nearer the light is smaller).
    let rate = -gnomon_depth_rate(view, p, to_light);
    // The receiver's plane: depth change per normalised map unit, through its tangents.
    let t1 = gnomon_perpendicular(n_geo);
    let t2 = cross(n_geo, t1);
    let tangent = mat2x2<f32>(vec2<f32>(dot(g[0], t1), dot(g[1], t1)), vec2<f32>(dot(g[0], t2), dot(g[1], t2)));
    let det = determinant(tangent);
    var depth_per_ndc = vec2<f32>(0.0);
    if (abs(det) > 1e-12 * max(dot(tangent[0], tangent[0]) + dot(tangent[1], tangent[1]), 1e-30)) {
        let inverse = mat2x2<f32>(vec2<f32>(tangent[1].y, -tangent[0].y), vec2<f32>(-tangent[1].x, tangent[0].x)) * (1.0 / det);
        let along = vec2<f32>(gnomon_depth_rate(view, p, t1), gnomon_depth_rate(view, p, t2));
        // depth = along . tau, tau = inverse ndc: a row vector along^T inverse.
        depth_per_ndc = vec2<f32>(dot(along, inverse[0]), dot(along, inverse[1]));
    }
    // The world radius (across the rays at p) that a blocker t world units toward the light
    // reaches within the light's area: a directional light's cone, a disc's (its image at
    // p's distance from the light, as perspective maps and paraboloids scale).
    let texel_per_world = 0.5 * view.resolution * sqrt(max(abs(determinant(jacobian)), 1e-30));
    let world_per_texel = 1.0 / max(texel_per_world, 1e-30);
    let t_max = max(at.reference, 0.0) / max(rate, 1e-30);
    var search = area * t_max;
    if (kind != GNOMON_LIGHT_DIRECTIONAL) {
        let t = min(t_max, 0.999 * distance);
        search = area * t / max(distance - t, 1e-30);
    }
    search = clamp(search, 0.0, GNOMON_PCSS_MAX_SEARCH_TEXELS * world_per_texel);
    // Blocker search: the mean depth of the texels nearer the light than the receiver's plane.
    var blockers = 0.0;
    var blocker_depth = 0.0;
    for (var i = 0; i < GNOMON_PCSS_SEARCH_TAPS; i++) {
        let offset = jacobian * (search * gnomon_vogel(i, GNOMON_PCSS_SEARCH_TAPS));
        let uv = gnomon_uv(at.ndc + offset);
        let stored = textureSampleLevel(
            gnomon_raw, gnomon_nearest, gnomon_layer_uv(view, uv), view.layer, 0.0).r;
        if (stored < at.reference + dot(depth_per_ndc, offset)) {
            blockers += 1.0;
            blocker_depth += stored;
        }
    }
    if (blockers == 0.0) {
        return 1.0;
    }
    // The penumbra's half-width at p from the blockers' distance t toward the light.
    let t = max(at.reference - blocker_depth / blockers, 0.0) / max(rate, 1e-30);
    var penumbra = area * t;
    if (kind != GNOMON_LIGHT_DIRECTIONAL) {
        let t_light = min(t, 0.999 * distance);
        penumbra = area * t_light / max(distance - t_light, 1e-30);
    }
    // At least half a texel (the hard shadow's own filter), at most the footprint's limit.
    let radius = clamp(penumbra, 0.5 * world_per_texel, GNOMON_PCSS_MAX_FILTER_TEXELS * world_per_texel);
    var lit = 0.0;
    for (var i = 0; i < GNOMON_PCSS_FILTER_TAPS; i++) {
        let offset = jacobian * (radius * gnomon_vogel(i, GNOMON_PCSS_FILTER_TAPS));
        let uv = gnomon_uv(at.ndc + offset);
        lit += textureSampleCompareLevel(gnomon_depth, gnomon_compare, gnomon_layer_uv(view, uv),
            view.layer, at.reference + dot(depth_per_ndc, offset));
    }
    return lit / f32(GNOMON_PCSS_FILTER_TAPS);
}

// One map's lookup at the surface point p (its normal offset applied).
fn gnomon_lookup_surface(map: u32, p: vec3<f32>, n_geo: vec3<f32>, n_dot_l: f32, filter_mode: u32) -> f32 {
    let view = gnomon_map_view(map);
    return gnomon_lookup_view(view, gnomon_offset_point(view, p, n_geo, n_dot_l), filter_mode);
}

// The shadow factor of `light` at the surface point p (1 lit, 0 shadowed) with `filter_mode`:
// the selected map, blended with the next cascade in its band, faded toward the shadow
// distance.
fn gnomon_shadow_filtered(light: u32, p: vec3<f32>, n_geo: vec3<f32>, n_dot_l: f32, filter_mode: u32) -> f32 {
    let s = gnomon_select(light, p);
    if (s.fade >= 1.0) {
        return 1.0;
    }
    var shadow = gnomon_read_surface(light, s.map, p, n_geo, n_dot_l, filter_mode);
    if (s.next_weight > 0.0) {
        let next = gnomon_read_surface(light, s.map + 1u, p, n_geo, n_dot_l, filter_mode);
        shadow = mix(shadow, next, s.next_weight);
    }
    return mix(shadow, 1.0, s.fade);
}

// The shadow factor of `light` at the surface point p (1 lit, 0 shadowed), with the frame's
// filter.
fn gnomon_shadow(light: u32, p: vec3<f32>, n_geo: vec3<f32>, n_dot_l: f32) -> f32 {
    return gnomon_shadow_filtered(light, p, n_geo, n_dot_l, gnomon_shadows.info.y);
}

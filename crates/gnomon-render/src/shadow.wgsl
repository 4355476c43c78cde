// gnomon's shadow-map passes.
//
// Depth pass (vs_depth / fs_depth): writes the linear light depth of `depth_from_world` plus a
// constant and slope-scaled bias, so that the bias is in world units whatever the map's warp.
// Main pass (vs_main / fs_main): ambient plus Lambert, the shadow factor from a comparison
// sampler (one tap, hardware 2x2 or 5x5 PCF), and the direct-light mask.

struct Globals {
    camera_clip_from_world: mat4x4<f32>,
    light_clip_from_world: mat4x4<f32>,
    depth_from_world: vec4<f32>,
    // xyz: the eye position.
    eye: vec4<f32>,
    // xyz: direction the light travels (w = 0) or the spot light's position (w = 1).
    light: vec4<f32>,
    // xyz: the spot's axis; w: cos of its half-angle.
    spot: vec4<f32>,
    // x: constant bias (depth units), y: slope scale (texels), z: largest slope bias (depth
    // units), w: normal offset (texels).
    bias: vec4<f32>,
    // x: resolution, y: shadow override (0 the map, 1 lit, 2 shadowed: shadow volumes),
    // z: filter (0 one tap, 1 hardware 2x2, 2 5x5 PCF),
    // w: ambient.
    map: vec4<f32>,
    // x: spot range, y: spot near distance, z: which terms to draw (0 ambient and direct
    // light, 1 the direct light only, 2 the ambient term only: shadow volumes draw the
    // ambient term once and add one light per pass).
    extra: vec4<f32>,
    // Two-map setups (SPPSM): the second map's matrices (the first map's again for one map),
    // the world plane on whose positive side a point reads the second map, and
    // x: 2 for two maps (else 1), y: 1 to tint (red: second map, blue: first), z: the second
    // map's resolution.
    light_clip_from_world_b: mat4x4<f32>,
    depth_from_world_b: vec4<f32>,
    plane: vec4<f32>,
    selection: vec4<f32>,
};

// Pipeline specialisations of the main pass: two maps (SPPSM), sampling metrics.
override TWO_MAPS: bool = false;
override METRICS: bool = false;

@group(0) @binding(0) var<uniform> g: Globals;
// The shadow maps, one layer each (two for SPPSM: layer 1 is the second map).
@group(0) @binding(1) var shadow_maps: texture_depth_2d_array;
@group(0) @binding(2) var shadow_linear: sampler_comparison;
@group(0) @binding(3) var shadow_nearest: sampler_comparison;

struct DepthOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) depth: f32,
};

@vertex
fn vs_depth(@location(0) position: vec3<f32>) -> DepthOut {
    var out: DepthOut;
    let p = vec4<f32>(position, 1.0);
    out.clip = g.light_clip_from_world * p;
    out.depth = dot(g.depth_from_world, p);
    return out;
}

@fragment
fn fs_depth(in: DepthOut) -> @builtin(frag_depth) f32 {
    // Slope-scaled bias: the depth change across one texel (the pass renders texels).
    let slope = max(abs(dpdx(in.depth)), abs(dpdy(in.depth)));
    let bias = g.bias.x + min(g.bias.y * slope, g.bias.z);
    return clamp(in.depth + bias, 0.0, 1.0);
}

struct MainOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) color: vec4<f32>,
};

@vertex
fn vs_main(
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) color: vec4<f32>,
) -> MainOut {
    var out: MainOut;
    out.clip = g.camera_clip_from_world * vec4<f32>(position, 1.0);
    out.world = position;
    out.normal = normal;
    out.color = color;
    return out;
}

struct Targets {
    @location(0) color: vec4<f32>,
    @location(1) mask: vec4<f32>,
    // x: pixels per texel along the worst direction (1 / sigma_min of the Jacobian of
    // texel coordinates by screen pixels), y: pixels per texel in area (1 / |det J|),
    // z: N.L (geometric normal toward the camera), w: 1 (geometry here). x and y are -1
    // where the map does not see the point.
    @location(2) metrics: vec4<f32>,
};

// Which map a point reads: the second one on the positive side of the plane (two maps).
fn reads_second_map(world: vec3<f32>) -> bool {
    return TWO_MAPS && dot(g.plane.xyz, world) + g.plane.w > 0.0;
}

// The map a point reads (chosen once per fragment): its matrices, resolution and layer.
struct MapView {
    clip_from_world: mat4x4<f32>,
    depth_from_world: vec4<f32>,
    resolution: f32,
    layer: i32,
};

fn map_view(second: bool) -> MapView {
    // Selects, not a branch: the fragments of a quad may read different maps.
    let a = g.light_clip_from_world;
    let b = g.light_clip_from_world_b;
    return MapView(
        mat4x4<f32>(
            select(a[0], b[0], second),
            select(a[1], b[1], second),
            select(a[2], b[2], second),
            select(a[3], b[3], second),
        ),
        select(g.depth_from_world, g.depth_from_world_b, second),
        select(g.map.x, g.selection.z, second),
        select(0, 1, second),
    );
}

// The world size of the largest texel side at a point: from the gradients of the map's
// normalised coordinates, (row_i - ndc_i row_w) / w, exact for any projective map (warps
// stretch texels differently along x and y).
fn texel_world_size(world: vec3<f32>, view: MapView) -> f32 {
    let m = view.clip_from_world;
    let clip = m * vec4<f32>(world, 1.0);
    if (clip.w <= 0.0) {
        return 0.0;
    }
    let row_x = vec3<f32>(m[0][0], m[1][0], m[2][0]);
    let row_y = vec3<f32>(m[0][1], m[1][1], m[2][1]);
    let row_w = vec3<f32>(m[0][3], m[1][3], m[2][3]);
    let gx = (row_x - (clip.x / clip.w) * row_w) / clip.w;
    let gy = (row_y - (clip.y / clip.w) * row_w) / clip.w;
    return (2.0 / view.resolution) / max(min(length(gx), length(gy)), 1e-30);
}

// 1 where the point is lit according to the shadow map, 0 where it is shadowed.
fn shadow_lookup(world: vec3<f32>, mode: i32, view: MapView) -> f32 {
    let clip = view.clip_from_world * vec4<f32>(world, 1.0);
    if (clip.w <= 0.0) {
        return 1.0;
    }
    let ndc = clip.xyz / clip.w;
    let uv = vec2<f32>(0.5 + 0.5 * ndc.x, 0.5 - 0.5 * ndc.y);
    let reference = dot(view.depth_from_world, vec4<f32>(world, 1.0));
    if (mode == 1) {
        return textureSampleCompareLevel(shadow_maps, shadow_linear, uv, view.layer, reference);
    }
    if (mode == 2) {
        let texel = 1.0 / view.resolution;
        var sum = 0.0;
        for (var y = -2; y <= 2; y++) {
            for (var x = -2; x <= 2; x++) {
                let offset = vec2<f32>(f32(x), f32(y)) * texel;
                sum += textureSampleCompareLevel(
                    shadow_maps, shadow_nearest, uv + offset, view.layer, reference);
            }
        }
        return sum / 25.0;
    }
    return textureSampleCompareLevel(shadow_maps, shadow_nearest, uv, view.layer, reference);
}

// The Jacobian of the map's texel coordinates by screen pixels at a point, reduced to
// (1 / sigma_min, 1 / |det|). Derivatives: call in uniform control flow.
fn sampling_metrics(world: vec3<f32>, m: mat4x4<f32>, resolution: f32) -> vec2<f32> {
    let clip = m * vec4<f32>(world, 1.0);
    let texel = (clip.xy / clip.w) * 0.5 * resolution;
    // Fine derivatives: each pixel's own row and column of its 2x2 quad.
    let jx = dpdxFine(texel);
    let jy = dpdyFine(texel);
    // J^T J = [[a, b], [b, c]]: its eigenvalues are the squared singular values.
    let a = dot(jx, jx);
    let b = dot(jx, jy);
    let c = dot(jy, jy);
    let half_trace = 0.5 * (a + c);
    let root = sqrt(max(0.25 * (a - c) * (a - c) + b * b, 0.0));
    let sigma_min = sqrt(max(half_trace - root, 0.0));
    let det = abs(jx.x * jy.y - jx.y * jy.x);
    if (clip.w <= 0.0) {
        return vec2<f32>(-1.0, -1.0);
    }
    // At most a million pixels per texel: a surface edge-on to the light is not resolved.
    return vec2<f32>(1.0 / max(sigma_min, 1e-6), 1.0 / max(det, 1e-6));
}

@fragment
fn fs_main(in: MainOut) -> Targets {
    // Both maps' metrics in uniform control flow (derivatives), then the one the point reads.
    let second = reads_second_map(in.world);
    // Only when asked for (a constant, so the branch is uniform control flow).
    var sampling = vec2<f32>(0.0, 0.0);
    if (METRICS) {
        let sampling_a = sampling_metrics(in.world, g.light_clip_from_world, g.map.x);
        let sampling_b = sampling_metrics(in.world, g.light_clip_from_world_b, g.selection.z);
        sampling = select(sampling_a, sampling_b, second);
    }
    // The geometric normal (the triangle's plane), turned toward the camera.
    var n_geo = normalize(cross(dpdx(in.world), dpdy(in.world)));
    let to_eye = g.eye.xyz - in.world;
    if (dot(n_geo, to_eye) < 0.0) {
        n_geo = -n_geo;
    }
    var n = normalize(in.normal);
    if (dot(n, to_eye) < 0.0) {
        n = -n;
    }

    var to_light: vec3<f32>;
    var cone = 1.0;
    var in_light = true;
    if (g.light.w < 0.5) {
        to_light = -g.light.xyz;
    } else {
        let d = g.light.xyz - in.world;
        to_light = normalize(d);
        let along = dot(-d, g.spot.xyz);
        let cos_angle = dot(-to_light, g.spot.xyz);
        in_light = cos_angle >= g.spot.w && along <= g.extra.x && along >= g.extra.y;
        cone = smoothstep(g.spot.w, min(g.spot.w + 0.03, 1.0), cos_angle);
    }
    let n_dot_l_geo = dot(n_geo, to_light);
    let facing = n_dot_l_geo > 0.0 && in_light;

    // Normal offset: move the lookup along the geometric normal by a fraction of a texel,
    // more where the light grazes the surface.
    let view = map_view(second);
    let offset = g.bias.w * texel_world_size(in.world, view) * clamp(1.0 - n_dot_l_geo, 0.0, 1.0);
    let lookup = in.world + n_geo * offset;

    var lit_one_tap = 1.0;
    var shadow = 1.0;
    if (in.color.w > 0.5) {
        if (g.map.y > 0.5) {
            // Shadow volumes: the stencil test chose this draw; map.y says which.
            lit_one_tap = select(0.0, 1.0, g.map.y < 1.5);
            shadow = lit_one_tap;
        } else {
            lit_one_tap = shadow_lookup(lookup, 0, view);
            shadow = shadow_lookup(lookup, i32(g.map.z), view);
        }
    }

    var out: Targets;
    let diffuse = max(dot(n, to_light), 0.0) * cone * shadow;
    let ambient = select(g.map.w, 0.0, g.extra.z > 0.5 && g.extra.z < 1.5);
    let direct = select(diffuse, 0.0, g.extra.z > 1.5 || !in_light);
    let light = ambient + (1.0 - g.map.w) * direct;
    var tint = vec3<f32>(1.0, 1.0, 1.0);
    if (TWO_MAPS && g.selection.y > 0.5) {
        tint = select(vec3<f32>(0.55, 0.7, 1.0), vec3<f32>(1.0, 0.55, 0.5), second);
    }
    out.color = vec4<f32>(in.color.rgb * light * tint, 1.0);
    let lit = facing && lit_one_tap > 0.5;
    out.mask = vec4<f32>(select(0.0, 1.0, lit), 0.0, 0.0, 1.0);
    out.metrics = vec4<f32>(sampling, n_dot_l_geo, 1.0);
    return out;
}

// Shadow volumes: homogeneous world positions (w = 0 at infinity) through the camera's
// infinite projection; stencil only.
@vertex
fn vs_volume(@location(0) position: vec4<f32>) -> @builtin(position) vec4<f32> {
    return g.camera_clip_from_world * position;
}

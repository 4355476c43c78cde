// The offscreen 3D view copied onto the window's surface texture, texel for texel: a
// triangle over the window, each pixel of the view's rectangle loading its texel (the
// view's texture is sRGB, so the load decodes it; an sRGB surface encodes it again, and a
// linear one gets it encoded here).

override ENCODE_SRGB: bool = false;

@group(0) @binding(0) var view: texture_2d<f32>;
// The rectangle's top-left corner in the window, in pixels.
@group(0) @binding(1) var<uniform> origin: vec4<u32>;

@vertex
fn vs_blit(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let uv = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    return vec4<f32>(uv * vec2<f32>(2.0, -2.0) + vec2<f32>(-1.0, 1.0), 0.0, 1.0);
}

fn encode(c: f32) -> f32 {
    if (c <= 0.0031308) {
        return c * 12.92;
    }
    return 1.055 * pow(c, 1.0 / 2.4) - 0.055;
}

@fragment
fn fs_blit(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    let texel = vec2<i32>(floor(position.xy)) - vec2<i32>(origin.xy);
    let c = textureLoad(view, texel, 0);
    if (ENCODE_SRGB) {
        return vec4<f32>(encode(c.r), encode(c.g), encode(c.b), c.a);
    }
    return c;
}

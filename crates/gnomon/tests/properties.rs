//! Property tests over twenty thousand of random cameras, lights and scenes, with the hard cases
//! drawn on purpose: light parallel to the view (miner's lamp), light toward the camera
//! (dueling frusta), light behind the camera, camera inside a box, grazing light, light
//! straight down, the LiSPSM paper's ideal configuration (the light perpendicular to the view
//! and equal to minus the camera's up vector, with near planes down to 10^-5 of the scene),
//! scenes from 1 m to 100 km. Visibility comes from the camera's own inputs (eye, forward,
//! up, lens), not from the camera code under test. `GNOMON_PROPTEST_CASES` sets the count
//! (default 20 000; the issue tracker's figures come from a run at 10^6).
//!
//! For every technique and configuration:
//! - the setup succeeds and every matrix is finite;
//! - uniform: every visible receiver point lands inside the inset square with 0 <= z <= 1;
//! - every visible receiver point that a caster can shadow (a caster point lies on the light
//!   ray through it, between it and the light) lands inside the inset square with
//!   0 <= z <= 1, and so does that caster point; no visible receiver point lands beyond the
//!   far plane (z > 1 would shadow it wrongly);
//! - the focused map covers the visible receivers at least as tightly as the uniform map
//!   (its inset square's footprint in the map plane is no larger);
//! - SPPSM (two maps and a plane): the same, for the map each receiver point's side of the
//!   plane picks, with its shadowing caster points in that same map;
//! - cascades (every fit: LiSPSM, focused with equal texels, PSM, TSM, XPSM; every split;
//!   stable): the same for the map of the point's slice and, in a blend band, the next
//!   slice's map too;
//! - point lights (anywhere in the scene, inside boxes too, or at the camera): `cube` and
//!   every single-map technique per face: each visible receiver point reads the map of its
//!   cube face, and lands inside it with its shadowing caster points (all on the same ray, so
//!   in the same face); a point whose face has no map has no caster that can shadow it; SPPSM
//!   and the cascades refuse point lights; dual paraboloid maps: each point and its shadowing
//!   caster points land inside the hemisphere it reads.

use glam::{DVec3, DVec4};
use gnomon::{
    Aabb, Camera, CascadeFit, CascadeSlices, CascadeSplit, Cascades, Cube, DirectionalLight,
    DualParaboloid, Focused, Lens, Light, Lispsm, MapProjection, MapSelection, MapSettings,
    PointLight, Psm, SceneBounds, ShadowMap, ShadowSetup, SpotLight, Sppsm, Technique, Tsm,
    Uniform, Xpsm, compute_setup,
};
use proptest::prelude::*;
use proptest::test_runner::TestRng;

/// One random configuration.
#[derive(Debug, Clone)]
struct Config {
    camera: Camera,
    /// What the camera was made from, to decide visibility independently of it.
    eye: DVec3,
    forward: DVec3,
    up: DVec3,
    lens: Lens,
    light: Light,
    scene: SceneBounds,
    /// Which hard case was drawn.
    case: &'static str,
}

const CASES: &[&str] = &[
    "random",
    "light_parallel_to_view",
    "light_toward_camera",
    "light_behind_camera",
    "camera_inside_box",
    "grazing_light",
    "light_straight_down",
    "spot",
    "spot_behind_camera",
    "ideal_configuration",
    "point",
    "point_at_camera",
];

fn unit_vector(rng: &mut TestRng) -> DVec3 {
    loop {
        let v = DVec3::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        );
        let l = v.length();
        if l > 0.1 && l <= 1.0 {
            return v / l;
        }
    }
}

/// A point drawn inside one of `boxes` (never empty: the ground is one).
fn inside_some_box(rng: &mut TestRng, boxes: &[Aabb]) -> DVec3 {
    let b = boxes[rng.random_range(0..boxes.len())];
    b.min()
        + (b.max() - b.min())
            * DVec3::new(
                rng.random_range(0.0..1.0),
                rng.random_range(0.0..1.0),
                rng.random_range(0.0..1.0),
            )
}

/// A spot or point light's range in a scene of size `s`: mostly `least` to 3 times `s`, and
/// one time in five a lamp whose range is a hundred thousandth to a tenth of the scene (its
/// near plane then lies under the scene's own tolerance).
fn light_range(rng: &mut TestRng, s: f64, least: f64) -> f64 {
    if rng.random_bool(0.2) {
        s * 10f64.powf(rng.random_range(-5.0..-1.0))
    } else {
        s * rng.random_range(least..3.0)
    }
}

fn random_box(rng: &mut TestRng, s: f64) -> Aabb {
    let c = DVec3::new(
        rng.random_range(-0.5..0.5) * s,
        0.0,
        rng.random_range(-0.5..0.5) * s,
    );
    let size = DVec3::new(
        s * 10f64.powf(rng.random_range(-3.0..-0.7)),
        s * 10f64.powf(rng.random_range(-3.0..-0.7)),
        s * 10f64.powf(rng.random_range(-3.0..-0.7)),
    );
    // Some float above the ground.
    let lift = if rng.random_bool(0.3) {
        rng.random_range(0.0..0.2) * s
    } else {
        0.0
    };
    Aabb::new(
        c + DVec3::new(-size.x, lift, -size.z) * DVec3::new(0.5, 1.0, 0.5),
        c + DVec3::new(size.x * 0.5, lift + size.y, size.z * 0.5),
    )
    .unwrap()
}

fn config(seed: u64) -> Config {
    let mut rng = TestRng::from_seed(proptest::test_runner::RngAlgorithm::ChaCha, &{
        let mut bytes = [0u8; 32];
        bytes[..8].copy_from_slice(&seed.to_le_bytes());
        bytes
    });
    let case = CASES[rng.random_range(0..CASES.len())];
    // Scene size: 1 m to 100 km.
    let s = 10f64.powf(rng.random_range(0.0..5.0));
    let ground = Aabb::new(
        DVec3::new(-0.5 * s, -0.01 * s, -0.5 * s),
        DVec3::new(0.5 * s, 0.0, 0.5 * s),
    )
    .unwrap();
    let mut casters = Vec::new();
    let mut receivers = vec![ground];
    if rng.random_bool(0.3) {
        casters.push(ground);
    }
    for _ in 0..rng.random_range(0..12) {
        let b = random_box(&mut rng, s);
        match rng.random_range(0..4) {
            0 => casters.push(b),
            1 => receivers.push(b),
            _ => {
                casters.push(b);
                receivers.push(b);
            }
        }
    }
    let scene_box = match rng.random_range(0..3) {
        0 => None,
        1 => Some(Aabb::new(DVec3::splat(-0.6 * s), DVec3::splat(0.6 * s)).unwrap()),
        // Too small: the scene box must grow.
        _ => Some(Aabb::new(DVec3::splat(-0.1 * s), DVec3::splat(0.1 * s)).unwrap()),
    };
    // The ideal configuration: a scene box that holds the far end of the view, so that the
    // frustum's side edges parallel to the light are edges of P (their ends then project to
    // one point, up to round-off).
    let scene_box = if case == "ideal_configuration" {
        Some(Aabb::new(DVec3::splat(-0.6 * s), DVec3::splat(0.6 * s)).unwrap())
    } else {
        scene_box
    };
    let scene = SceneBounds::new(casters.clone(), receivers.clone(), scene_box).unwrap();

    let near = s * 10f64.powf(rng.random_range(-5.0..-2.0));
    let mut far = (near * 10f64.powf(rng.random_range(1.0..5.0))).min(1e8);
    if rng.random_bool(0.7) {
        // Mostly a far plane that reaches across the scene.
        far = far.max(s * rng.random_range(0.3..3.0));
    }
    if case == "ideal_configuration" {
        // A far plane inside the scene.
        far = s * rng.random_range(0.2..0.8);
    }
    let lens = Lens {
        fov_y_degrees: rng.random_range(10.0..120.0),
        aspect: rng.random_range(0.3..2.5),
        near,
        far: far.max(near * 2.0),
    };
    let mut eye = DVec3::new(
        rng.random_range(-0.7..0.7) * s,
        rng.random_range(0.001..0.3) * s,
        rng.random_range(-0.7..0.7) * s,
    );
    let all: Vec<Aabb> = casters.iter().chain(receivers.iter()).copied().collect();
    if case == "camera_inside_box" {
        eye = inside_some_box(&mut rng, &all);
    }
    let mut view = unit_vector(&mut rng);
    if rng.random_bool(0.7) {
        // Mostly look toward the scene.
        let target = DVec3::new(
            rng.random_range(-0.5..0.5) * s,
            0.0,
            rng.random_range(-0.5..0.5) * s,
        );
        if (target - eye).length() > 1e-6 * s {
            view = (target - eye).normalize();
        }
    }
    let mut light_dir = unit_vector(&mut rng);
    if light_dir.y > 0.0 && rng.random_bool(0.8) {
        light_dir.y = -light_dir.y;
    }
    let jitter =
        |rng: &mut TestRng, v: DVec3, amount: f64| (v + amount * unit_vector(rng)).normalize();
    match case {
        "light_parallel_to_view" => {
            light_dir = if rng.random_bool(0.5) {
                view
            } else {
                jitter(&mut rng, view, 1e-4)
            };
        }
        "light_toward_camera" => {
            light_dir = if rng.random_bool(0.5) {
                -view
            } else {
                jitter(&mut rng, -view, 0.2)
            }
        }
        "light_behind_camera" => light_dir = jitter(&mut rng, view, 0.5),
        "grazing_light" => {
            let a = rng.random_range(0.0..std::f64::consts::TAU);
            light_dir =
                DVec3::new(a.cos(), -10f64.powf(rng.random_range(-4.0..-1.0)), a.sin()).normalize();
        }
        "light_straight_down" => {
            light_dir = -DVec3::Y;
            if rng.random_bool(0.3) {
                view = -DVec3::Y;
            }
        }
        _ => {}
    }
    let mut up = if view.cross(DVec3::Y).length() > 1e-3 {
        DVec3::Y
    } else {
        DVec3::Z
    };
    if case == "ideal_configuration" {
        // The LiSPSM paper's ideal configuration: the light perpendicular to the view and
        // equal to minus the camera's up vector (any roll about the view axis).
        let side = view.any_orthonormal_vector();
        let roll = rng.random_range(0.0..std::f64::consts::TAU);
        up = side * roll.cos() + view.cross(side) * roll.sin();
        if up.y < 0.0 && rng.random_bool(0.8) {
            up = -up;
        }
        light_dir = if rng.random_bool(0.8) {
            -up
        } else {
            jitter(&mut rng, -up, 1e-6)
        };
    }
    let camera = Camera::look_at(eye, eye + view, up, lens).unwrap();
    let light = match case {
        "spot" | "spot_behind_camera" => {
            let position = if case == "spot" && rng.random_bool(0.2) {
                // A lamp inside its lantern (or in a wall).
                inside_some_box(&mut rng, &all)
            } else if case == "spot" {
                DVec3::new(
                    rng.random_range(-0.6..0.6) * s,
                    rng.random_range(0.01..0.5) * s,
                    rng.random_range(-0.6..0.6) * s,
                )
            } else {
                eye - view * rng.random_range(0.001..0.2) * s
                    + DVec3::Y * rng.random_range(0.0..0.05) * s
            };
            let aim = if case == "spot" {
                DVec3::new(
                    rng.random_range(-0.5..0.5) * s,
                    0.0,
                    rng.random_range(-0.5..0.5) * s,
                ) - position
            } else {
                view
            };
            let direction = if aim.length() > 1e-6 * s {
                aim
            } else {
                -DVec3::Y
            };
            let range = light_range(&mut rng, s, 0.2);
            Light::Spot(
                SpotLight::new(position, direction, rng.random_range(5.0..80.0), range).unwrap(),
            )
        }
        "point" | "point_at_camera" => {
            let position = if case == "point" && rng.random_bool(0.2) {
                inside_some_box(&mut rng, &all)
            } else if case == "point" {
                DVec3::new(
                    rng.random_range(-0.6..0.6) * s,
                    rng.random_range(0.002..0.3) * s,
                    rng.random_range(-0.6..0.6) * s,
                )
            } else {
                // A headlamp: at the eye, or a little above and behind it.
                eye + if rng.random_bool(0.5) {
                    DVec3::ZERO
                } else {
                    (DVec3::Y - view) * rng.random_range(0.0..0.02) * s
                }
            };
            Light::Point(PointLight::new(position, light_range(&mut rng, s, 0.1)).unwrap())
        }
        _ => Light::Directional(DirectionalLight::new(light_dir).unwrap()),
    };
    Config {
        camera,
        eye,
        forward: view,
        up,
        lens,
        light,
        scene,
        case,
    }
}

/// Whether the camera sees `p`, from its inputs alone: in front between the near and far
/// planes, inside the field of view (a thousandth of the near distance of slack at the sides,
/// so that points on the frustum's faces count).
fn sees(cfg: &Config, p: DVec3) -> bool {
    let forward = cfg.forward.normalize();
    let right = forward.cross(cfg.up).normalize();
    let up = right.cross(forward);
    let q = p - cfg.eye;
    let d = q.dot(forward);
    let t = (0.5 * cfg.lens.fov_y_degrees.to_radians()).tan();
    d >= cfg.lens.near
        && d <= cfg.lens.far
        && q.dot(up).abs() <= d * t
        && q.dot(right).abs() <= d * t * cfg.lens.aspect
}

/// Receiver surface points the camera sees (and, for a spot light, inside its frustum).
fn visible_receiver_points(cfg: &Config, rng: &mut TestRng) -> Vec<DVec3> {
    let mut out = Vec::new();
    for r in cfg.scene.receivers() {
        for k in 0..24 {
            let (lo, hi) = (r.min(), r.max());
            let mut p = lo
                + (hi - lo)
                    * DVec3::new(
                        rng.random_range(0.0..1.0),
                        rng.random_range(0.0..1.0),
                        rng.random_range(0.0..1.0),
                    );
            if k % 2 == 0 {
                // On a face: snap one coordinate.
                let axis = rng.random_range(0..3);
                p[axis] = if rng.random_bool(0.5) {
                    lo[axis]
                } else {
                    hi[axis]
                };
            }
            if sees(cfg, p) && lit_by_spot(&cfg.light, p) {
                out.push(p);
            }
        }
    }
    out
}

/// Whether `p` is inside a spot light's cone and range, or a point light's range beyond the
/// near plane of its face (always true for a directional light).
fn lit_by_spot(light: &Light, p: DVec3) -> bool {
    match light {
        Light::Directional(_) => true,
        Light::Point(l) => {
            let q = p - l.position();
            let along = q.dot(PointLight::face_of(q).axis());
            along >= l.near() * 1.001 && q.length() <= l.range()
        }
        Light::Spot(s) => {
            let q = p - s.position();
            let d = q.dot(s.direction());
            d >= s.near() * 1.001 && d <= s.range() && q.length() * s.half_angle().cos() <= d
        }
    }
}

/// Caster points on the light ray through `r`, between `r` and the light: the ray's entry,
/// exit and middle in each caster box it crosses.
fn shadowing_caster_points(cfg: &Config, r: DVec3) -> Vec<DVec3> {
    // The ray r + t (toward - r) for t in [0, t_max].
    let (toward, t_max) = match &cfg.light {
        Light::Directional(l) => (r - l.direction(), f64::INFINITY),
        Light::Spot(s) => {
            // Stop at the light's near plane: closer casters are clipped by design.
            let d = (r - s.position()).dot(s.direction());
            (s.position(), 1.0 - s.near() * 1.001 / d)
        }
        Light::Point(l) => {
            // The same, at the near plane of the ray's cube face.
            let q = r - l.position();
            let d = q.dot(PointLight::face_of(q).axis());
            (l.position(), 1.0 - l.near() * 1.001 / d)
        }
    };
    let dir = toward - r;
    let mut out = Vec::new();
    for c in cfg.scene.casters() {
        let (mut t0, mut t1) = (0.0f64, t_max);
        for axis in 0..3 {
            if dir[axis].abs() < 1e-300 {
                if r[axis] < c.min()[axis] || r[axis] > c.max()[axis] {
                    t0 = f64::INFINITY;
                }
                continue;
            }
            let a = (c.min()[axis] - r[axis]) / dir[axis];
            let b = (c.max()[axis] - r[axis]) / dir[axis];
            t0 = t0.max(a.min(b));
            t1 = t1.min(a.max(b));
        }
        if t0 <= t1 && t1.is_finite() {
            for t in [t0, 0.5 * (t0 + t1), t1] {
                out.push(r + dir * t);
            }
        }
    }
    out
}

/// Tolerance for "inside" checks in normalised device coordinates.
const EPS: f64 = 1e-6;

fn lands_inside(map: &ShadowMap, p: DVec3) -> Result<DVec3, String> {
    let ndc = map
        .project(p)
        .ok_or_else(|| format!("{p} is behind the map's centre"))?;
    let s = map.inset_ndc() + EPS;
    if ndc.x.abs() > s || ndc.y.abs() > s || ndc.z < -EPS || ndc.z > 1.0 + EPS {
        return Err(format!(
            "{p} lands at {ndc}, outside the inset square {s} or depth [0, 1]"
        ));
    }
    let depth = map.linear_depth(p);
    if !(-EPS..=1.0 + EPS).contains(&depth) {
        return Err(format!("{p} has linear depth {depth}"));
    }
    Ok(ndc)
}

/// The world-space footprint area of the map's inset square on the map plane.
fn footprint(map: &ShadowMap, light: &Light) -> f64 {
    let m = map.clip_from_world;
    let (rx, ry, rw) = (
        m.row(0).truncate(),
        m.row(1).truncate(),
        m.row(3).truncate(),
    );
    let axis = if rw.length() > 0.0 {
        rw.normalize()
    } else {
        light.direction()
    };
    let s = 2.0 * map.inset_ndc();
    s * s / (rx.cross(axis).length() * ry.cross(axis).length())
}

fn check(cfg: &Config, seed: u64) -> Result<(), String> {
    let settings = MapSettings::with_resolution(1024);
    let setup = |t: Technique| -> Result<ShadowSetup, String> {
        compute_setup(&t, &cfg.camera, &cfg.light, &cfg.scene, settings).map_err(|e| format!("{e}"))
    };
    if matches!(cfg.light, Light::Point(_)) {
        return check_point(cfg, seed, setup);
    }
    let uniform = setup(Technique::Uniform(Uniform))?;
    let focused = setup(Technique::Focused(Focused))?;
    let lispsm = setup(Technique::Lispsm(Lispsm::default()))?;
    let tsm = setup(Technique::Tsm(Tsm::default()))?;
    let xpsm = setup(Technique::Xpsm(Xpsm::default()))?;
    let psm = setup(Technique::Psm(Psm::default()))?;
    let sppsm = setup(Technique::Sppsm(Sppsm::default()))?;
    let cascades = setup(Technique::Cascades(Cascades::default()))?;
    let focused_cascades = setup(Technique::Cascades(Cascades {
        fit: CascadeFit::Focused,
        count: 3,
        blend: 0.3,
        equal_texels: true,
        ..Cascades::default()
    }))?;
    let stable = setup(Technique::Cascades(Cascades {
        stable: true,
        count: 5,
        ..Cascades::default()
    }))?;
    // Every other fit inside cascades, each with its own split and band.
    let fits = [
        (CascadeFit::Psm(Psm::default()), CascadeSplit::Log, 0.2),
        (CascadeFit::Tsm(Tsm::default()), CascadeSplit::Uniform, 0.5),
        (
            CascadeFit::Xpsm(Xpsm::default()),
            CascadeSplit::FirstThenLog { first: 3.0 },
            0.1,
        ),
    ]
    .map(|(fit, split, blend)| {
        setup(Technique::Cascades(Cascades {
            fit,
            split,
            blend,
            count: 3,
            ..Cascades::default()
        }))
    });
    let [psm_cascades, tsm_cascades, xpsm_cascades] = fits;
    let (psm_cascades, tsm_cascades, xpsm_cascades) =
        (psm_cascades?, tsm_cascades?, xpsm_cascades?);
    let mut rng = TestRng::from_seed(
        proptest::test_runner::RngAlgorithm::ChaCha,
        &[seed as u8; 32],
    );
    let points = visible_receiver_points(cfg, &mut rng);
    let from_a_point = matches!(cfg.light, Light::Spot(_));
    for setup in [
        &uniform,
        &focused,
        &lispsm,
        &tsm,
        &xpsm,
        &psm,
        &sppsm,
        &cascades,
        &focused_cascades,
        &stable,
        &psm_cascades,
        &tsm_cascades,
        &xpsm_cascades,
    ] {
        for map in &setup.maps {
            if !(map.clip_from_world.is_finite() && map.depth_from_world.is_finite()) {
                return Err(format!("{}: non-finite matrix", setup.technique));
            }
        }
        for &r in &points {
            // Two-map setups: the receiver reads the map its side of the plane picks, and the
            // casters shadowing it (on the same light ray, so on the same side) must be there.
            // Cascades: the map of its slice, and the next one in a blend band.
            let casters = shadowing_caster_points(cfg, r);
            for k in maps_read(setup, r) {
                check_map(setup, &setup.maps[k], r, &casters, from_a_point)?;
            }
        }
    }
    let (fu, ff) = (
        footprint(&uniform.maps[0], &cfg.light),
        footprint(&focused.maps[0], &cfg.light),
    );
    if ff > fu * (1.0 + 1e-6) {
        return Err(format!(
            "focused footprint {ff} exceeds the uniform footprint {fu}"
        ));
    }
    Ok(())
}

/// [`check`] for a point light: every technique that takes one, per cube face.
fn check_point(
    cfg: &Config,
    seed: u64,
    setup: impl Fn(Technique) -> Result<ShadowSetup, String>,
) -> Result<(), String> {
    for refused in [
        Technique::Sppsm(Sppsm::default()),
        Technique::Cascades(Cascades::default()),
    ] {
        if setup(refused).is_ok() {
            return Err(format!("{refused:?} took a point light"));
        }
    }
    let setups = [
        setup(Technique::Cube(Cube))?,
        setup(Technique::Uniform(Uniform))?,
        setup(Technique::Focused(Focused))?,
        setup(Technique::Lispsm(Lispsm::default()))?,
        setup(Technique::Psm(Psm::default()))?,
        setup(Technique::Tsm(Tsm::default()))?,
        setup(Technique::Xpsm(Xpsm::default()))?,
        setup(Technique::Lispsm(Lispsm {
            limit: false,
            ..Lispsm::default()
        }))?,
    ];
    let mut rng = TestRng::from_seed(
        proptest::test_runner::RngAlgorithm::ChaCha,
        &[seed as u8; 32],
    );
    let points = visible_receiver_points(cfg, &mut rng);
    // Dual paraboloid maps: the hemisphere a point's direction falls in holds it and its
    // shadowing caster points.
    let paraboloid = setup(Technique::Paraboloid(DualParaboloid))?;
    for &r in &points {
        let casters = shadowing_caster_points(cfg, r);
        let k = paraboloid.map_for(r).unwrap();
        check_map(&paraboloid, &paraboloid.maps[k], r, &casters, true)?;
    }
    for setup in &setups {
        let MapSelection::CubeFaces(faces) = setup.selection else {
            return Err(format!(
                "{}: selection {:?}",
                setup.technique, setup.selection
            ));
        };
        if faces.faces().len() != setup.maps.len() || setup.maps.is_empty() {
            return Err(format!(
                "{}: {} maps for {:?}",
                setup.technique,
                setup.maps.len(),
                faces.faces()
            ));
        }
        if setup.maps.len() + setup.diagnostics.cube_faces_skipped != 6 {
            return Err(format!(
                "{}: maps and skipped faces do not add up to six",
                setup.technique
            ));
        }
        for map in &setup.maps {
            if !map.is_finite() {
                return Err(format!("{}: non-finite matrix", setup.technique));
            }
        }
        for &r in &points {
            let casters = shadowing_caster_points(cfg, r);
            match setup.map_for(r) {
                Some(k) => check_map(setup, &setup.maps[k], r, &casters, true)?,
                None if casters.is_empty() => {}
                None => {
                    return Err(format!(
                        "{}: {r} can be shadowed, but its face {:?} has no map ({:?})",
                        setup.technique,
                        PointLight::face_of(r - faces.position),
                        faces.faces()
                    ));
                }
            }
        }
    }
    Ok(())
}

/// The maps a receiver point reads: the one its selection picks and, in a cascade's blend
/// band, the next; none beyond a cascade's shadow distance.
fn maps_read(setup: &ShadowSetup, r: DVec3) -> Vec<usize> {
    let k = setup.map_for(r).unwrap();
    let MapSelection::Cascades(c) = setup.selection else {
        return vec![k];
    };
    let depth = c.depth_row_world.dot(r.extend(1.0));
    let z = c.depths();
    if depth >= c.shadow_distance() {
        return Vec::new();
    }
    let slice = c.slice_of(depth);
    if c.by_coverage && k < slice {
        // Picked by coverage: the band is the outer `blend` of the map's square, toward the
        // next map where that is the slice's or holds the point (as the lookup reads it).
        let next = k + 1 == slice || CascadeSlices::covers(&setup.maps[k + 1], r);
        return if c.blend > 0.0 && next && cover_extent(&setup.maps[k], r) > 1.0 - c.blend {
            vec![k, k + 1]
        } else {
            vec![k]
        };
    }
    let band = c.blend * (z[k + 1] - z[k]);
    if k + 1 < c.count && depth > z[k + 1] - band {
        vec![k, k + 1]
    } else {
        vec![k]
    }
}

/// How far out in `map`'s square less its cover margin `p` lies (1: at its edge), as the
/// lookup measures it for a map picked by coverage.
fn cover_extent(map: &ShadowMap, p: DVec3) -> f64 {
    let border = (map.viewport_inset + CascadeSlices::COVER_MARGIN_TEXELS) as f64;
    let limit = 1.0 - 2.0 * border / map.resolution as f64;
    let clip = map.clip_from_world * p.extend(1.0);
    clip.x.abs().max(clip.y.abs()) / limit
}

/// How far below 1 the clip-space z of a relevant caster point of a map seen from a point
/// must stay: far more than the few f32 roundings a rasteriser makes (a spot light's or cube
/// face's near plane lies at a millionth of the range, and the usual perspective z put every
/// point beyond a few near distances within 1e-6 of 1, where the rasteriser clipped a whole
/// face's casters in random scene 159).
const POINT_MAP_CLIP_Z_MARGIN: f64 = 1e-3;

/// One map read by receiver point `r` (with the caster points shadowing it): see the module
/// documentation. `from_a_point`: the light is a spot or point light (its perspective maps'
/// clip z must keep [`POINT_MAP_CLIP_Z_MARGIN`] from the far end).
fn check_map(
    setup: &ShadowSetup,
    map: &ShadowMap,
    r: DVec3,
    casters: &[DVec3],
    from_a_point: bool,
) -> Result<(), String> {
    let ctx = |e: String| {
        format!(
            "{} ({:?}): receiver: {e}",
            setup.technique, setup.diagnostics.fallbacks
        )
    };
    if setup.technique == "uniform" || !casters.is_empty() {
        lands_inside(map, r).map_err(ctx)?;
    } else if let Some(ndc) = map.project(r) {
        // Not shadowable: it may fall outside the focus region, but never beyond the far
        // plane, where it would compare as shadowed.
        if ndc.z > 1.0 + EPS && ndc.x.abs() <= 1.0 && ndc.y.abs() <= 1.0 {
            return Err(ctx(format!("{r} lands beyond the far plane at {ndc}")));
        }
    }
    for &q in casters {
        let ndc = lands_inside(map, q).map_err(|e| {
            format!(
                "{} ({:?}): caster point shadowing {r}: {e}",
                setup.technique, setup.diagnostics.fallbacks
            )
        })?;
        if from_a_point
            && map.projection == MapProjection::Perspective
            && ndc.z > 1.0 - POINT_MAP_CLIP_Z_MARGIN
        {
            return Err(format!(
                "{} ({:?}): caster point {q} shadowing {r} lands at clip z {}, within f32 roundings of the far end",
                setup.technique, setup.diagnostics.fallbacks, ndc.z
            ));
        }
    }
    Ok(())
}

/// Cases of the property test: `GNOMON_PROPTEST_CASES`, or 20 000.
fn cases() -> u32 {
    std::env::var("GNOMON_PROPTEST_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(20_000)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: cases(), failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn setups_cover_receivers_and_never_clip_a_caster(seed in any::<u64>()) {
        let cfg = config(seed);
        if let Err(e) = check(&cfg, seed) {
            prop_assert!(false, "case {} (seed {seed}): {e}\n{cfg:?}", cfg.case);
        }
    }
}

/// Seeds the random run once failed on, checked every time.
const SEEDS_THAT_ONCE_FAILED: &[u64] = &[
    // Stable cascades picked by coverage: the first map holds a far point, and the test read
    // the second too by the depth band of its slice, where the lookup reads only the first.
    1889226656986228439,
    // A sun straight down over a camera looking straight down: the ground and a box's base
    // lie exactly on the border where a TSM cascade's blend band meets the next slice.
    14212840576244645804,
    // A spot of 1 cm range, half a metre above the ground of a 300 m scene: its near plane
    // (1e-8 from it) lay under the scene's tolerance, and a projected point at depth 0 made
    // PSM's matrix NaN.
    9569696694855184225,
    // A spot of 4 cm range inside a box: points kept within the tolerance outside its sides
    // project outside its square by a thousandth near the light, and the focused map came out
    // larger than the uniform one.
    955261120470776306,
];

#[test]
fn seeds_that_once_failed() {
    for &seed in SEEDS_THAT_ONCE_FAILED {
        let cfg = config(seed);
        if let Err(e) = check(&cfg, seed) {
            panic!("case {} (seed {seed}): {e}", cfg.case);
        }
    }
}

/// The convex body B (LiSPSM section 3.3) holds every point the camera sees inside the scene
/// box: the warps build their maps around B, so a visible point outside it can land outside
/// the map (in the ideal configuration a hull edge between two corners that project to one
/// point, up to round-off, once cut B through the view).
fn check_body(cfg: &Config, seed: u64) -> Result<usize, String> {
    if matches!(cfg.light, Light::Point(_)) {
        // A point light's B is its faces' (each a spot light's, checked as such).
        return Ok(0);
    }
    let body = gnomon::convex_body_b(&cfg.camera, &cfg.light, &cfg.scene);
    let scene_box = cfg.scene.scene_box();
    let (lo, hi) = (scene_box.min(), scene_box.max());
    let mut rng = TestRng::from_seed(
        proptest::test_runner::RngAlgorithm::ChaCha,
        &[(seed >> 8) as u8; 32],
    );
    // Points of the view: along rays through the image, at depths between near and far.
    let forward = cfg.forward.normalize();
    let right = forward.cross(cfg.up).normalize();
    let up = right.cross(forward);
    let t = (0.5 * cfg.lens.fov_y_degrees.to_radians()).tan();
    let mut points = Vec::new();
    for _ in 0..200 {
        let (x, y) = (rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0));
        let u = rng.random_range(0.0..1.0f64);
        let d = cfg.lens.near * (cfg.lens.far / cfg.lens.near).powf(u);
        let p = cfg.eye + d * (forward + x * t * cfg.lens.aspect * right + y * t * up);
        if p.cmpge(lo).all() && p.cmple(hi).all() && lit_by_spot(&cfg.light, p) {
            points.push(p);
        }
    }
    if points.is_empty() {
        return Ok(0);
    }
    if body.is_empty() {
        return Err(format!("B is empty, yet the camera sees {}", points[0]));
    }
    let vertices = body.vertices(0.0);
    let centroid = vertices.iter().copied().sum::<DVec3>() / vertices.len() as f64;
    let extent = (hi - lo).length() + (cfg.eye - scene_box.center()).length();
    for plane in body.bounding_planes(centroid, 1e-9 * extent) {
        for &p in &points {
            let d = plane.distance(p);
            if d < -1e-7 * extent {
                return Err(format!("{p} lies {:.3e} outside B", -d));
            }
        }
    }
    Ok(points.len())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: cases(), failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn the_focus_body_holds_the_visible_scene(seed in any::<u64>()) {
        let cfg = config(seed);
        if let Err(e) = check_body(&cfg, seed) {
            prop_assert!(false, "case {} (seed {seed}): {e}\n{cfg:?}", cfg.case);
        }
    }
}

/// Unit cube clipping's XY is the casters' extents intersected with the visible receivers'
/// (the blog post's rule): the focused map covers no more than the casters' boxes span, nor
/// more than the receivers' boxes span, in its own coordinates (checked on the boxes' corners,
/// a superset of what the map fits to). A map fitted to the receivers alone would spread over
/// a ground that does not cast (613 times the area for a post on such ground).
fn check_tightness(cfg: &Config) -> Result<bool, String> {
    if matches!(cfg.light, Light::Point(_)) {
        return Ok(false);
    }
    let setup = compute_setup(
        &Focused,
        &cfg.camera,
        &cfg.light,
        &cfg.scene,
        MapSettings::with_resolution(1024),
    )
    .map_err(|e| e.to_string())?;
    if !setup.diagnostics.fallbacks.is_empty() {
        return Ok(false);
    }
    let map = setup.maps[0];
    let s = map.inset_ndc();
    let span = |boxes: &[Aabb]| -> Option<(DVec3, DVec3)> {
        let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
        for b in boxes {
            for c in b.corners() {
                let n = map.project(c)?;
                lo = lo.min(n);
                hi = hi.max(n);
            }
        }
        Some((lo, hi))
    };
    for (what, boxes) in [
        ("casters", cfg.scene.casters()),
        ("receivers", cfg.scene.receivers()),
    ] {
        // Corners behind a spot light's map: no bound from this side.
        let Some((lo, hi)) = span(boxes) else {
            return Ok(false);
        };
        // The extents' padding (a millionth of their size plus the setup's tolerance, which
        // is large against a small map in a large scene) stays below a hundredth; a map
        // fitted to the receivers alone is off by far more.
        let slack = 1e-2 * s;
        // An axis on which casters and receivers barely meet collapses to a sliver whose
        // size is its padding (the setup's absolute tolerance): no relative bound there.
        let scale =
            cfg.scene.scene_box().diagonal() + (cfg.eye - cfg.scene.scene_box().center()).length();
        let m = map.clip_from_world;
        let half = |row: usize| s / m.row(row).truncate().length();
        let (check_x, check_y) = (half(0) > 1e-5 * scale, half(1) > 1e-5 * scale);
        if (check_x && (lo.x > -s + slack || hi.x < s - slack))
            || (check_y && (lo.y > -s + slack || hi.y < s - slack))
        {
            return Err(format!(
                "the focused map covers more than the {what}' boxes span: their NDC span {lo} to {hi}, the square {s}"
            ));
        }
    }
    Ok(true)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: cases(), failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn the_focused_map_is_no_wider_than_casters_and_receivers(seed in any::<u64>()) {
        let cfg = config(seed);
        if let Err(e) = check_tightness(&cfg) {
            prop_assert!(false, "case {} (seed {seed}): {e}\n{cfg:?}", cfg.case);
        }
    }
}

/// The hard cases fire the fallbacks they should, so the property test above exercises them.
#[test]
fn hard_cases_are_drawn_and_name_their_fallbacks() {
    let mut seen = std::collections::BTreeMap::<&str, usize>::new();
    let mut parallel_fallbacks = 0;
    for seed in 0..2000u64 {
        let cfg = config(seed);
        *seen.entry(cfg.case).or_default() += 1;
        let setup = compute_setup(
            &Focused,
            &cfg.camera,
            &cfg.light,
            &cfg.scene,
            MapSettings::default(),
        )
        .unwrap();
        if cfg.case == "light_parallel_to_view"
            && setup
                .diagnostics
                .fallbacks
                .contains(&gnomon::Fallback::LightParallelToView)
        {
            parallel_fallbacks += 1;
        }
    }
    for case in CASES {
        assert!(
            seen.get(case).copied().unwrap_or(0) > 100,
            "case {case} drawn too rarely: {seen:?}"
        );
    }
    assert!(
        parallel_fallbacks > 50,
        "the parallel fallback fired {parallel_fallbacks} times"
    );
}

#[test]
fn depth_row_matches_the_clip_depth_for_orthographic_maps() {
    for seed in 0..200u64 {
        let cfg = config(seed);
        if matches!(cfg.light, Light::Spot(_) | Light::Point(_)) {
            continue;
        }
        let setup = compute_setup(
            &Focused,
            &cfg.camera,
            &cfg.light,
            &cfg.scene,
            MapSettings::default(),
        )
        .unwrap();
        let m = setup.maps[0];
        let row = m.clip_from_world.row(2);
        let scale = row.truncate().length().max(1e-300);
        assert!(
            ((row - m.depth_from_world) / scale).abs().max_element() < 1e-9,
            "{row} vs {}",
            m.depth_from_world
        );
        let _ = DVec4::ZERO;
    }
}

/// The property test checks many points: most configurations see receivers, and many
/// receiver points are shadowable, in every hard case.
#[test]
fn property_checks_are_not_vacuous() {
    let mut per_case = std::collections::BTreeMap::<&str, (usize, usize, usize)>::new();
    for seed in 0..1500u64 {
        let cfg = config(seed);
        let mut rng = TestRng::from_seed(
            proptest::test_runner::RngAlgorithm::ChaCha,
            &[seed as u8; 32],
        );
        let points = visible_receiver_points(&cfg, &mut rng);
        let entry = per_case.entry(cfg.case).or_default();
        entry.0 += usize::from(!points.is_empty());
        for r in points {
            let casters = shadowing_caster_points(&cfg, r);
            entry.1 += usize::from(!casters.is_empty());
            entry.2 += casters.len();
        }
    }
    for (case, (configs_with_points, shadowable, caster_points)) in &per_case {
        println!(
            "{case}: {configs_with_points} configurations see receivers, {shadowable} shadowable receiver points, {caster_points} caster points"
        );
        assert!(
            *configs_with_points > 40,
            "{case}: too few configurations see a receiver"
        );
        assert!(
            *shadowable > 200,
            "{case}: too few shadowable receiver points"
        );
    }
}

/// Spot lights are warped (LiSPSM and PSM after the light's perspective), not handed to the
/// focused map: in the spot cases, most configurations that see receivers get a warped map
/// with no fallback, so the property test above checks the spot warps themselves.
#[test]
fn spot_lights_are_warped_by_lispsm_and_psm() {
    let mut seen = 0;
    let mut warped = [0usize; 2];
    for seed in 0..3000u64 {
        let cfg = config(seed);
        if !matches!(cfg.light, Light::Spot(_)) {
            continue;
        }
        // The warps themselves (the limit may choose the focused map instead).
        let techniques = [
            Technique::Lispsm(Lispsm {
                limit: false,
                ..Lispsm::default()
            }),
            Technique::Psm(Psm {
                limit: false,
                ..Psm::default()
            }),
        ];
        for (i, t) in techniques.iter().enumerate() {
            let setup = compute_setup(
                t,
                &cfg.camera,
                &cfg.light,
                &cfg.scene,
                MapSettings::default(),
            )
            .unwrap();
            if i == 0 && setup.diagnostics.visible_receivers > 0 {
                seen += 1;
            }
            assert!(
                !setup
                    .diagnostics
                    .fallbacks
                    .contains(&gnomon::Fallback::SpotLightNotWarped)
            );
            if setup.diagnostics.visible_receivers > 0 && setup.diagnostics.fallbacks.is_empty() {
                assert_eq!(setup.maps[0].projection, gnomon::MapProjection::Perspective);
                warped[i] += 1;
            }
        }
    }
    println!(
        "spot configurations seeing receivers: {seen}; warped: lispsm {}, psm {}",
        warped[0], warped[1]
    );
    assert!(seen > 200, "{seen}");
    for (name, n) in ["lispsm", "psm"].iter().zip(warped) {
        assert!(2 * n > seen, "{name}: {n} of {seen} warped");
    }
}

/// The tightness property checks most configurations (those with no fallback and every box
/// corner in front of a spot light's map).
#[test]
fn tightness_checks_are_not_vacuous() {
    let checked = (0..2000u64)
        .filter(|&seed| check_tightness(&config(seed)) == Ok(true))
        .count();
    println!("tightness checked in {checked} of 2000 configurations");
    assert!(checked > 600, "{checked}");
    // Found at 10^6 cases: casters and receivers barely meet on one axis (a grazing light),
    // and the map is a sliver there.
    assert!(check_tightness(&config(1643661818672702969)).is_ok());
}

//! The LiSPSM paper's ideal configuration (the light perpendicular to the view and equal to
//! minus the camera's up vector), with the two cases that lost shadows: PSM, LiSPSM and XPSM
//! (and SPPSM through PSM) placed visible, shadowed ground points outside their maps (xy far
//! outside the inset square, or w < 0).
//!
//! Root cause: in this configuration the light direction lies in the frustum's left and right
//! planes, so the view body P has edges parallel to the light whose two ends project to one
//! point of the map plane, up to round-off (1e-15 apart). The 2D hull kept both, and the
//! silhouette plane through the edge between them had a direction made of round-off: it cut
//! the convex body B (LiSPSM section 3.3) through the view, and the warps built around B left
//! visible points out. The hull now merges vertices that coincide to a trillionth of its
//! extent, and B skips hull edges too short to have a direction (leaving a silhouette plane
//! out only enlarges B).

use glam::DVec3;
use gnomon::{
    Aabb, Camera, DirectionalLight, Lens, Light, MapSettings, SceneBounds, Technique, compute_setup,
};

/// The 30 boxes (casters that also receive) of a 32 m scene in which the first case lost
/// its shadow: drawn at random as the property test draws scenes.
const BOXES_NEAR_THE_GROUND: [([f64; 3], [f64; 3]); 30] = [
    (
        [5.138769743827963, 0.0, 12.347552727902272],
        [11.282047166378605, 0.03333862410813943, 12.752172868623187],
    ),
    (
        [14.755104057490893, 1.7383088866815308, 10.287258777797573],
        [14.912888428234428, 1.8182823939723047, 14.779715863797554],
    ),
    (
        [-6.768903000836612, 0.0, -5.05999533834855],
        [-6.655758826298018, 1.961219525497144, -4.8720561682959165],
    ),
    (
        [-14.73780034316549, 2.829189011822955, 10.574602389070048],
        [-14.050789711590808, 2.9280735502223556, 10.65077967819495],
    ),
    (
        [-12.003175122868596, 0.0, -14.01318246213954],
        [
            -11.967081100028738,
            0.07391294577847553,
            -11.931828662741996,
        ],
    ),
    (
        [-14.516451151055861, 0.0, -3.352817875740713],
        [-14.472689033884727, 1.2626833617882283, -1.7477821437239336],
    ),
    (
        [5.900677141168577, 0.0, -9.373022862697555],
        [6.401996210283258, 0.037476818941803845, -3.5228809172196853],
    ),
    (
        [7.255887808731311, 0.0, -14.760421351781751],
        [7.462172098552589, 0.10320966700574387, -12.361731489633897],
    ),
    (
        [-14.43391968649209, 0.0, 8.309960316449246],
        [-13.853440925498095, 2.428796270247989, 8.58971052554984],
    ),
    (
        [-1.1401102028693337, 0.0, 4.198595051591596],
        [1.0793405228504018, 1.1736755418083653, 5.503634989253053],
    ),
    (
        [10.803225396719487, 0.0, -1.1721457893679592],
        [17.213705818989148, 2.2418410594577414, 2.603328834277102],
    ),
    (
        [2.597930155691721, 2.3851237789427637, -8.984207841813957],
        [2.744643418509558, 2.710609791121262, -8.90994990667083],
    ),
    (
        [14.667015434983929, 0.0, -1.9787750452090425],
        [15.190067583301099, 0.07066722161091883, 3.188589756740548],
    ),
    (
        [-4.637537507178044, 6.240055889073655, -8.009738181017795],
        [-4.506630577973732, 6.412379642654234, -5.015099908321656],
    ),
    (
        [-12.751895377929767, 0.0, -7.7179189207853875],
        [
            -12.581685667674886,
            0.05963054553315822,
            -7.6490802746218565,
        ],
    ),
    (
        [5.969781341094389, 0.0, 15.171977264874577],
        [6.018903281227999, 0.15699488783051666, 15.208418849426717],
    ),
    (
        [-9.782628719421691, 2.7791689732994467, 8.99145866953453],
        [-9.731912898894347, 8.379657148579568, 10.579652572195862],
    ),
    (
        [11.261733023916687, 0.0, -15.917714054507586],
        [13.445148867943605, 0.06910650468911095, -15.668235312168042],
    ),
    (
        [13.556054081840932, 0.0, -16.268877418325175],
        [14.54028862176826, 3.2983941466948696, -15.730764318987358],
    ),
    (
        [-10.223951610489065, 0.3281034125250685, 3.543240306597674],
        [-9.147106925735327, 4.355776525292908, 3.7174489529373678],
    ),
    (
        [12.680658479809841, 0.0, 4.76142093622826],
        [12.743580607356245, 5.919530902006221, 7.613108484744404],
    ),
    (
        [5.59118515128489, 4.585749206391323, -15.941588466981944],
        [6.65318886509878, 4.984325049197516, -15.035338497345641],
    ),
    (
        [11.613533631138095, 5.358033469667791, 8.0956552670154],
        [11.984628138419042, 7.6574085302842265, 8.76995359102965],
    ),
    (
        [11.334752874612594, 0.0, 10.589854400388367],
        [12.166412644555553, 3.4273963468100095, 10.859658972613945],
    ),
    (
        [-11.343171255719808, 0.0, -5.616240394376654],
        [-9.544232824415255, 2.8211415904522337, -0.5650106528132302],
    ),
    (
        [15.81641972723087, 0.0, -4.0617746875119245],
        [15.874677698173434, 0.6626286014087992, -2.327352566917035],
    ),
    (
        [6.891486148532689, 0.0, 11.587767743338638],
        [11.517325094244885, 0.4610304319007431, 13.400199665792162],
    ),
    (
        [12.75965962876786, 0.0, -1.726206018429864],
        [12.859919515031208, 0.2650309298239601, -1.6147799066440716],
    ),
    (
        [-7.000584591745461, 0.7445058249772448, 4.124098791563266],
        [-3.82657216302737, 4.762625643094564, 4.1940357367909895],
    ),
    (
        [13.786494633557925, 2.467765502416596, 13.681669565226061],
        [13.887109207384928, 5.524902607578678, 14.47483044489069],
    ),
];

struct Case {
    camera: Camera,
    light: Light,
    scene: SceneBounds,
    /// A visible ground point in the shadow of a caster.
    point: DVec3,
}

/// The camera looking along `forward` with `up`, the light travelling along `sun`.
fn camera(eye: DVec3, forward: DVec3, up: DVec3, lens: Lens) -> Camera {
    Camera::look_at(eye, eye + forward, up, lens).unwrap()
}

fn case(
    camera: Camera,
    sun: DVec3,
    ground_half: f64,
    boxes: &[([f64; 3], [f64; 3])],
    scene_box: Option<(DVec3, DVec3)>,
    point: DVec3,
) -> Case {
    let light = Light::Directional(DirectionalLight::new(sun).unwrap());
    let ground = Aabb::new(
        DVec3::new(-ground_half, -0.01 * ground_half, -ground_half),
        DVec3::new(ground_half, 0.0, ground_half),
    )
    .unwrap();
    // A caster on the light ray above the point, so that the point is shadowed.
    let size = 0.01 * ground_half;
    let above = point - sun.normalize() * 5.0 * size;
    let caster = Aabb::new(above - DVec3::splat(size), above + DVec3::splat(size)).unwrap();
    // Given boxes shadow the point themselves.
    let mut casters = if boxes.is_empty() {
        vec![caster]
    } else {
        vec![]
    };
    casters.extend(
        boxes
            .iter()
            .map(|(lo, hi)| Aabb::new(DVec3::from(*lo), DVec3::from(*hi)).unwrap()),
    );
    let mut receivers = casters.clone();
    receivers.push(ground);
    let scene = SceneBounds::new(
        casters,
        receivers,
        scene_box.map(|(lo, hi)| Aabb::new(lo, hi).unwrap()),
    )
    .unwrap();
    Case {
        camera,
        light,
        scene,
        point,
    }
}

/// The first case of the issue (a 32 m scene seen from 0.24 m above the ground, near plane
/// 1.6 mm).
fn near_the_ground() -> Case {
    case(
        camera(
            DVec3::new(12.77290181403474, 0.2383400832511522, 13.840931457504787),
            DVec3::new(-0.626967034496259, -0.528870548385932, -0.5720212239986646),
            DVec3::new(
                -0.39069567623194135,
                0.8487025056225319,
                -0.3564560919997055,
            ),
            Lens {
                fov_y_degrees: 99.3308074193156,
                aspect: 0.4074350120072408,
                near: 0.0015958901889251559,
                far: 18.573228365202898,
            },
        ),
        DVec3::new(0.3906956762319413, -0.8487025056225319, 0.3564560919997055),
        16.1764,
        &BOXES_NEAR_THE_GROUND,
        None,
        DVec3::new(10.355923015711342, 0.0, 12.716363354995202),
    )
}

/// The second case (a 44 km scene, the point 8 km away). The issue does not give its 30
/// casters: here a scene box that holds the view's far end stands in for them.
fn kilometres() -> Case {
    case(
        camera(
            DVec3::new(17379.13, 45.271, 9376.64),
            DVec3::new(-0.77007, -0.52479, -0.36275),
            DVec3::new(-0.47476, 0.85123, -0.22364),
            Lens {
                fov_y_degrees: 83.57,
                aspect: 0.5766,
                near: 37.6,
                far: 16484.8,
            },
        ),
        DVec3::new(0.47476, -0.85123, 0.22364),
        21786.0,
        &[],
        Some((
            DVec3::new(-21786.0, -217.9, -21786.0),
            DVec3::new(21786.0, 9000.0, 21786.0),
        )),
        DVec3::new(7634.50, 0.0, 7659.87),
    )
}

#[test]
fn shadowed_points_in_the_ideal_configuration_land_inside_every_map() {
    for (name, c) in [
        ("near the ground", near_the_ground()),
        ("kilometres", kilometres()),
    ] {
        for technique in Technique::all().into_iter().filter(|t| t.takes(&c.light)) {
            let setup = compute_setup(
                &technique,
                &c.camera,
                &c.light,
                &c.scene,
                MapSettings::with_resolution(2048),
            )
            .unwrap();
            let map = &setup.maps[setup.map_for(c.point).unwrap()];
            let ndc = map.project(c.point);
            let s = map.inset_ndc() + 1e-9;
            assert!(
                ndc.is_some_and(|n| n.x.abs() <= s && n.y.abs() <= s),
                "{name}, {}: the shadowed point {} lands at {ndc:?} (w = {})",
                setup.technique,
                c.point,
                (map.clip_from_world * c.point.extend(1.0)).w
            );
        }
    }
}

#[test]
fn the_focus_body_holds_the_view_in_the_ideal_configuration() {
    for (name, c) in [
        ("near the ground", near_the_ground()),
        ("kilometres", kilometres()),
    ] {
        let body = gnomon::convex_body_b(&c.camera, &c.light, &c.scene);
        let vertices = body.vertices(0.0);
        let centroid = vertices.iter().copied().sum::<DVec3>() / vertices.len() as f64;
        for plane in body.bounding_planes(centroid, 1e-9) {
            assert!(
                plane.distance(c.point) > -1e-6,
                "{name}: the point lies {} outside B",
                -plane.distance(c.point)
            );
        }
    }
}

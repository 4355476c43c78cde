//! Runs `examples/embed.rs`: both ways of embedding gnomon in a plain wgpu program give the
//! image `Renderer::render` gives for the same view.

#[path = "../examples/embed.rs"]
#[allow(dead_code)]
mod embed;

#[test]
fn both_ways_of_embedding_agree_with_the_headless_render() {
    let report = embed::run().unwrap_or_else(|e| panic!("GPU tests need an adapter: {e}"));
    println!(
        "A: {:.3}%, B: {:.3}%",
        100.0 * report.agreement_a,
        100.0 * report.agreement_b
    );
    assert!(report.agreement_a >= 0.99, "A: {}", report.agreement_a);
    assert!(report.agreement_b >= 0.99, "B: {}", report.agreement_b);
    // The images show shadows: the reference has shaded and sky pixels of many values.
    let mut values: Vec<&[u8]> = report.reference.chunks_exact(4).collect();
    values.sort();
    values.dedup();
    assert!(values.len() > 100, "{} distinct colours", values.len());
    // Where the light does not reach (shadowed or facing away), B matches too: without the
    // lookup its cast shadows would be lit (B then matches on 98.5% of all pixels).
    let unlit: Vec<usize> = (0..report.mask.len())
        .filter(|&i| report.mask[i] == gnomon_render::MASK_UNLIT)
        .collect();
    let matching = unlit
        .iter()
        .filter(|&&i| {
            (0..3).all(|c| report.own_pass[4 * i + c].abs_diff(report.reference[4 * i + c]) <= 3)
        })
        .count();
    println!("B in the dark: {matching} of {} pixels", unlit.len());
    assert!(unlit.len() > 2000 && matching as f64 >= 0.99 * unlit.len() as f64);
}

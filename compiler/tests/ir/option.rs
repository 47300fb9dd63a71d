#[derive(Clone, Copy)]
struct Hit {
    t: f32,
    id: u32,
}

fn intersect(t: f32) -> Option<Hit> {
    if t > 0.0 {
        Some(Hit { t, id: 7 })
    } else {
        None
    }
}

fn trax_main() {
    if let Some(h) = intersect(trax::rand()) {
        trax::store_u32(0, h.id);
    }
}

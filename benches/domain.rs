//! Criterion bench of the domain map (docs/spec.md §5): 720 x 720 cells, Eq. (14), one thread,
//! <= 100 ms.

use criterion::{Criterion, criterion_group, criterion_main};
use freefloat::analysis::domain::DomainMap;
use freefloat::{Mount, RobotParams, Transform};
use std::hint::black_box;

fn bench_domain(c: &mut Criterion) {
    for (name, a, b) in [("a0.1_b0.1", 0.1, 0.1), ("a1_b-1", 1.0, -1.0)] {
        let robot = RobotParams::src().with_mount(Mount::new(a, b).expect("finite")).expect("valid");
        c.bench_function(&format!("domain_map_720/{name}"), |bench| {
            bench.iter(|| black_box(DomainMap::new(black_box(&robot), Transform::Eq14, 720).expect("map")))
        });
    }
}

criterion_group!(benches, bench_domain);
criterion_main!(benches);

//! A free flexible FFR body with no damping and no gravity (a synthetic body: random nodal
//! masses, positions and two basis rows per node, lumped M_ff = Σ mⱼ Ψⱼᵀ Ψⱼ, diagonal K_ff):
//! linear momentum Σ mⱼ ẋⱼ, angular momentum Σ mⱼ xⱼ × ẋⱼ (summed over the nodes here) and
//! the energy T + ½ q_fᵀ K q_f stay constant up to BDF1's first-order drift, which halves
//! with Δt.

use faer::Mat;
use paraflex::geometry::euler_parameters::{
    from_axis_angle, rotated_vector_jacobian, rotation_matrix,
};
use paraflex::geometry::{mat3, vec3};
use paraflex::linalg::random::SplitMix64;
use paraflex::multibody::flexible::NodalMass;
use paraflex::multibody::{Body, FlexibleBodyData, Ggl, MassInvariants, NewtonSettings, System};

const MODES: usize = 2;

fn nodes() -> Vec<NodalMass> {
    let mut rng = SplitMix64::new(21);
    (0..8)
        .map(|_| NodalMass {
            mass: 0.5 + rng.unit(),
            position: [0.0; 3].map(|_| rng.symmetric()),
            modes: (0..MODES)
                .map(|_| [0.0; 3].map(|_| 0.2 * rng.symmetric()))
                .collect(),
        })
        .collect()
}

/// Linear and angular momentum of the nodes at the integrator's state.
fn momenta(ggl: &Ggl, nodes: &[NodalMass]) -> ([f64; 3], [f64; 3]) {
    let (q, v) = (&ggl.q, &ggl.v);
    let e = [q[3], q[4], q[5], q[6]];
    let e_dot = [v[3], v[4], v[5], v[6]];
    let a = rotation_matrix(&e);
    let (mut p, mut h) = ([0.0; 3], [0.0; 3]);
    for node in nodes {
        let mut u = node.position;
        let mut w = [0.0; 3];
        for k in 0..MODES {
            u = vec3::add(u, vec3::scale(node.modes[k], q[7 + k]));
            w = vec3::add(w, vec3::scale(node.modes[k], v[7 + k]));
        }
        let x = vec3::add([q[0], q[1], q[2]], mat3::mul_vec(&a, u));
        let d = rotated_vector_jacobian(&e, u);
        let turning: [f64; 3] = std::array::from_fn(|i| (0..4).map(|b| d[i][b] * e_dot[b]).sum());
        let xdot = vec3::add(vec3::add([v[0], v[1], v[2]], turning), mat3::mul_vec(&a, w));
        p = vec3::add(p, vec3::scale(xdot, node.mass));
        h = vec3::add(h, vec3::scale(vec3::cross(x, xdot), node.mass));
    }
    (p, h)
}

fn run(dt: f64) -> [f64; 3] {
    let nodes = nodes();
    let m_ff = Mat::from_fn(MODES, MODES, |k, l| {
        nodes
            .iter()
            .map(|n| n.mass * vec3::dot(n.modes[k], n.modes[l]))
            .sum::<f64>()
    });
    let stiffness = Mat::from_fn(
        MODES,
        MODES,
        |k, l| if k == l { 25.0 * m_ff[(k, k)] } else { 0.0 },
    );
    let mut sys = System::new([0.0; 3]);
    let body = sys.add_body(
        Body::flexible(FlexibleBodyData {
            invariants: MassInvariants::from_nodes(&nodes),
            mass: m_ff,
            stiffness: stiffness.clone(),
            damping: Mat::zeros(MODES, MODES),
            interfaces: Vec::new(),
        }),
        [0.0; 3],
        from_axis_angle([0.3, 1.0, -0.2], 0.5).unwrap(),
    );
    sys.set_initial_velocity(body, [0.2, -0.1, 0.05], [0.4, -0.3, 0.8]);
    sys.set_initial_modal(body, &[0.05, -0.03]);
    let mut ggl = Ggl::new(sys, dt, 0.0, NewtonSettings::default()).unwrap();
    let energy = |g: &Ggl| {
        let qf = &g.q[7..];
        g.kinetic_energy()
            + 0.5
                * (0..MODES)
                    .map(|k| {
                        (0..MODES)
                            .map(|l| qf[k] * stiffness[(k, l)] * qf[l])
                            .sum::<f64>()
                    })
                    .sum::<f64>()
    };
    let (p0, h0) = momenta(&ggl, &nodes);
    let e0 = energy(&ggl);
    ggl.run((0.5 / dt).round() as usize, |_, _| {}).unwrap();
    let (p1, h1) = momenta(&ggl, &nodes);
    let relative = |a: [f64; 3], b: [f64; 3]| vec3::norm(vec3::sub(a, b)) / vec3::norm(a);
    [
        relative(p0, p1),
        relative(h0, h1),
        (energy(&ggl) - e0).abs() / e0,
    ]
}

#[test]
fn free_flexible_body_conserves_momentum_and_energy_to_first_order() {
    let coarse = run(1e-3);
    let fine = run(5e-4);
    for (i, name) in ["linear momentum", "angular momentum", "energy"]
        .iter()
        .enumerate()
    {
        assert!(coarse[i] < 1e-2, "{name} drift {:e}", coarse[i]);
        let ratio = coarse[i] / fine[i];
        assert!(
            fine[i] < 1e-12 || (1.6..2.4).contains(&ratio),
            "{name}: drift {:e} at Δt, {:e} at Δt/2",
            coarse[i],
            fine[i]
        );
    }
}

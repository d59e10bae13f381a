//! Outputs of the current state of a [`Ggl`] integration as plain data: marker positions,
//! velocities and accelerations (eq. 2.58–2.59), joint reactions, drive coordinates, efforts
//! and power, kinetic energy.

use super::integrator::{Ggl, StepReport};
use super::joints::JointKind;
use super::system::DriveSource;

impl Ggl {
    /// Global position of a marker point (eq. 2.58).
    pub fn marker_position(&self, marker: usize) -> [f64; 3] {
        self.system.markers[marker]
            .point()
            .value(&self.system.layout, &self.q)
    }

    /// Global velocity of a marker point.
    pub fn marker_velocity(&self, marker: usize) -> [f64; 3] {
        self.system.markers[marker]
            .point()
            .rate(&self.system.layout, &self.q, &self.v)
    }

    /// Global acceleration of a marker point (eq. 2.59): (∂p/∂q) q̈ + q̇ᵀ ∂²p/∂q² q̇, with q̈ the
    /// BDF1 difference of the last step.
    pub fn marker_acceleration(&self, marker: usize) -> [f64; 3] {
        let p = self.system.markers[marker].point();
        let layout = &self.system.layout;
        let mut a = p.rate(layout, &self.q, &self.acceleration);
        let convective = p.convective_acceleration(layout, &self.q, &self.v);
        for i in 0..3 {
            a[i] += convective[i];
        }
        a
    }

    /// The force the joint applies to its first marker's body (global components), for joints
    /// whose first three rows make the points coincide; `None` otherwise.
    pub fn joint_force(&self, joint: usize) -> Option<[f64; 3]> {
        let kind = self.system.joints[joint].kind;
        let coincident = matches!(
            kind,
            JointKind::Spherical | JointKind::Revolute | JointKind::Fixed | JointKind::Universal
        );
        coincident.then(|| {
            let l = self.joint_multipliers(joint);
            // rows eₖ·(p₁ − p₂): the force on body 1 is −Σ λₖ eₖ
            [-l[0], -l[1], -l[2]]
        })
    }

    /// A drive's joint coordinate and its rate (θ, θ̇ or s, ṡ).
    pub fn drive_coordinate(&self, drive: usize) -> [f64; 2] {
        let joint = self.system.drives[drive].joint;
        let coordinate = match self.equations.drive_sources[drive] {
            DriveSource::Spring(i) => self.equations.springs[i].coordinate.clone(),
            DriveSource::Row(_) => self.system.joint_coordinate(joint),
        };
        let mut gradient = vec![0.0; self.system.size()];
        let value = coordinate.evaluate(&self.system.layout, &self.q, &mut gradient);
        let rate = gradient.iter().zip(&self.v).map(|(g, v)| g * v).sum();
        [value, rate]
    }

    /// The power a drive delivers, effort × coordinate rate (eq. 6.1 f₂ integrates it).
    pub fn drive_power(&self, drive: usize) -> f64 {
        self.drive_effort(drive) * self.drive_coordinate(drive)[1]
    }

    /// Kinetic energy ½ q̇ᵀ M q̇ of the system.
    pub fn kinetic_energy(&self) -> f64 {
        self.system.kinetic_energy(&self.q, &self.v)
    }

    /// Runs `steps` steps, calling `observe` after each.
    pub fn run(
        &mut self,
        steps: usize,
        mut observe: impl FnMut(&Ggl, &StepReport),
    ) -> Result<(), super::MultibodyError> {
        for _ in 0..steps {
            let report = self.step()?;
            observe(self, &report);
        }
        Ok(())
    }
}

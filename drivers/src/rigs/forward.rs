//! [`forward_rig!`]: the [`magbench_trackers::Rig`] methods of a type forwarded to a field.

/// Implements [`magbench_trackers::Rig`] for `$t` by forwarding every method to field `$f`.
macro_rules! forward_rig {
    ($t:ty, $f:ident) => {
        impl magbench_trackers::Rig for $t {
            fn frame_period(&self) -> f64 {
                magbench_trackers::Rig::frame_period(&self.$f)
            }
            fn observe(
                &mut self,
            ) -> Result<magbench_env::plant::Observation, magbench_trackers::RigError> {
                magbench_trackers::Rig::observe(&mut self.$f)
            }
            fn command(
                &mut self,
                u: &magbench_env::Control,
            ) -> Result<(), magbench_trackers::RigError> {
                magbench_trackers::Rig::command(&mut self.$f, u)
            }
            fn stop(&mut self) -> Result<(), magbench_trackers::RigError> {
                magbench_trackers::Rig::stop(&mut self.$f)
            }
            fn latency(&self) -> f64 {
                magbench_trackers::Rig::latency(&self.$f)
            }
            fn set_world(
                &mut self,
                w: &magbench_env::World,
            ) -> Result<(), magbench_trackers::RigError> {
                magbench_trackers::Rig::set_world(&mut self.$f, w)
            }
            fn ground_truth(&self) -> Option<magbench_trackers::GroundTruth> {
                magbench_trackers::Rig::ground_truth(&self.$f)
            }
        }
    };
}

pub(super) use forward_rig;

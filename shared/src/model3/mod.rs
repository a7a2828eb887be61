//! Model 3, the rig as built (issue 34), on the host (the crate's feature `model3`): the
//! pneumatic band drive ([`cylinder`], [`pneumatic_run`]). (Unilateral contact and the contact
//! that stiffens with load live where model 2's equations are built: `model2::event_run::edges`
//! and [`crate::Scene::contact_stiffnesses`].)

pub mod cylinder;
pub mod pneumatic_run;

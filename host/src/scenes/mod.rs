//! Scenes and their runs: the built-in scenes ([`builtin`]), scene files ([`scene_file`]) and
//! where a command's scene comes from ([`scene_source`]); one run of a scene ([`run`]; statistics at event speed, [`event`]), its
//! time series ([`series`]) and cycles ([`cycles`]), and the linear stability of its steady
//! sliding ([`sliding`]).

pub mod builtin;
pub mod cycles;
pub mod event;
pub(crate) mod grid_run;
pub mod run;
pub mod scene_file;
pub mod scene_source;
pub mod series;
pub mod pneumatic;
pub mod unilateral;
pub mod sliding;
pub mod table_cache;
pub mod wide_runs;

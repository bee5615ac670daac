//! Campaigns: many analyses of one scene's variants (a grid over scene keys
//! and/or a seeded Monte Carlo sample), run resumably on this machine or as
//! a Slurm job array, and collected into one table with convergence and
//! distribution summaries. See `docs/campaigns.md`.
//!
//! Layers: [`file`](mod@file) parses the campaign file, [`sample`] draws tolerances,
//! [`variants`] resolves jobs and their identities, [`resources`] estimates
//! memory, [`store`] keeps the job folders, [`task`] runs one job,
//! [`local`] is the local executor, [`slurm`] the Slurm one, [`collect`] (with
//! [`crate::grid_convergence`], [`stats`], [`plots`]) gathers the [`table`]
//! and its summaries, [`parquet`] writes the table. The analyses themselves run
//! through the `flank` executable (a child process per job): nothing here
//! imports the analysis code, and no lower layer imports this one.

pub mod collect;
pub mod file;
pub mod local;
pub mod parquet;
pub mod plots;
pub mod resources;
pub mod sample;
pub mod slurm;
pub mod stats;
pub mod store;
pub mod table;
pub mod task;
pub mod variants;

pub use file::{read_campaign_file, CampaignFile};
pub use variants::{flank_version, Campaign, Job};

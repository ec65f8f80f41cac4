//! Nothing to build: this manifest only names bevy_pbr for `cargo fetch`.

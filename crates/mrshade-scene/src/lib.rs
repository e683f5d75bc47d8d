//! mrshade-scene: what a mixed-reality session is, and how it is read from disk.
//!
//! A [`Session`] ties together a glTF proxy of the real scene with the inserted virtual
//! content ([`Scene`]), the camera photo (or a posed image sequence, [`Sequence`]), the real
//! light probe and the render settings. The input contract is `shared/data/README.md`
//! ("Conventions"): metres, +Y up, cameras and lights looking down local −Z, `extras.real`
//! flags inherited by children, radiometric light intensities, and the equirectangular probe
//! mapping of `mrshade_core::math`.
//!
//! Every loader rejects bad input with an error that names the file and the field; nothing
//! here panics on user data.

pub mod assets;
pub mod budget;
pub mod gltf;
pub mod images;
pub mod model;
pub mod sequence;
pub mod session;

pub use assets::AssetSource;
pub use model::{AlphaMode, Camera, Instance, Light, LightKind, Material, Primitive, Scene, Texture, TextureRef};
pub use model::{Animation, Channel, Interpolation, NodeLinks, SceneNode, ScenePose, TargetPath, Trs};
pub use model::{Deformation, MorphTarget, Placement, Skin, VertexSkin, deform_vertices};
pub use model::{UNIT_TOLERANCE, checked_rotation, checked_scale, checked_translation};
pub use sequence::{Sequence, SequenceFrame};
pub use session::{Environment, OutputSize, Session, SessionOverrides};

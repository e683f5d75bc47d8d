//! Small scenes built in code for the path tracer's known-answer tests.
#![allow(dead_code, missing_docs)]

use glam::{Mat4, Vec2, Vec3};
use mrshade_core::HdrImage;
use mrshade_core::flags::Realness;
use mrshade_core::settings::{ReferenceSettings, RenderSettings};
use mrshade_scene::{Camera, Environment, Instance, Light, LightKind, Material, OutputSize, Primitive, Scene, Session};
use mrshade_testkit::gltf::{self, Shape};

pub fn lambert(albedo: f32) -> Material {
    Material {
        name: "lambert".into(),
        base_color: Vec3::splat(albedo).extend(1.0),
        metallic: 0.0,
        specular: 0.0,
        ..Material::default()
    }
}

/// A scene under construction.
pub struct Builder {
    pub scene: Scene,
    pub environment: Option<Environment>,
    pub photo: f32,
}

impl Builder {
    /// A camera at `eye` looking along `forward` (unit), vertical field of view 0.8 rad.
    pub fn new(eye: Vec3, forward: Vec3) -> Builder {
        let up = if forward.y.abs() > 0.9 { Vec3::NEG_Z } else { Vec3::Y };
        let world_from_camera = glam::camera::rh::view::look_to_mat4(eye, forward, up).inverse();
        let camera = Camera {
            node_name: "camera".into(),
            camera_name: None,
            yfov: 0.8,
            aspect_ratio: None,
            znear: 0.01,
            world_from_camera,
        };
        Builder { scene: Scene { cameras: vec![camera], ..Scene::default() }, environment: None, photo: 0.5 }
    }

    pub fn uniform_probe(&mut self, radiance: f32) -> &mut Self {
        self.environment =
            Some(Environment { image: HdrImage::filled(16, 8, [radiance; 3]), rotation_deg: 0.0, intensity: 1.0 });
        self
    }

    /// Places a testkit shape at `offset` with its own material.
    fn add(&mut self, shape: Shape, offset: Vec3, material: Material, realness: Realness) -> &mut Self {
        self.scene.materials.push(material);
        self.scene.primitives.push(Primitive {
            name: "shape".into(),
            positions: shape.positions.into_iter().map(Vec3::from).collect(),
            normals: shape.normals.into_iter().map(Vec3::from).collect(),
            uvs: shape.uvs.into_iter().map(Vec2::from).collect(),
            indices: shape.indices,
            material: self.scene.materials.len() - 1,
            ..Default::default()
        });
        self.scene.instances.push(Instance {
            node_name: "shape".into(),
            primitive: self.scene.primitives.len() - 1,
            world_from_object: Mat4::from_translation(offset),
            realness,
            skin: None,
            morph_weights: Vec::new(),
        });
        self
    }

    /// A square of side 2·`half` in the plane y = `y`, facing up (u along +x, v along +z).
    pub fn floor(&mut self, half: f32, y: f32, material: Material, realness: Realness) -> &mut Self {
        self.add(gltf::quad(half), Vec3::Y * y, material, realness)
    }

    /// An axis-aligned box, outward normals (flat).
    pub fn cuboid(&mut self, center: Vec3, half: Vec3, material: Material, realness: Realness) -> &mut Self {
        self.add(gltf::cuboid(half.to_array()), center, material, realness)
    }

    /// A UV sphere with smooth normals (96 segments, 48 rings).
    pub fn sphere(&mut self, center: Vec3, radius: f32, material: Material, realness: Realness) -> &mut Self {
        self.add(gltf::sphere(radius, 96), center, material, realness)
    }

    /// A spot light at `position` shining straight down.
    pub fn spot_down(&mut self, position: Vec3, intensity: f32, cones: (f32, f32), realness: Realness) -> &mut Self {
        self.spot(position, Vec3::NEG_Y, intensity, cones, realness)
    }

    /// A spot light at `position` shining along `direction` (unit).
    pub fn spot(
        &mut self,
        position: Vec3,
        direction: Vec3,
        intensity: f32,
        cones: (f32, f32),
        realness: Realness,
    ) -> &mut Self {
        let rotation = glam::Quat::from_rotation_arc(Vec3::NEG_Z, direction);
        self.scene.lights.push(Light {
            name: "spot".into(),
            kind: LightKind::Spot { inner_cone: cones.0, outer_cone: cones.1 },
            intensity: Vec3::splat(intensity),
            world_from_light: Mat4::from_rotation_translation(rotation, position),
            realness,
        });
        self
    }

    pub fn session(&self, width: u32, height: u32, settings: ReferenceSettings) -> Session {
        Session {
            origin: "test".into(),
            scene: self.scene.clone(),
            camera: 0,
            background: HdrImage::filled(width, height, [self.photo; 3]),
            exposure: 1.0,
            environment: self.environment.clone(),
            output: OutputSize { width, height, supersample: 1, frames: 1 },
            settings: RenderSettings { reference: settings, ..RenderSettings::default() },
            limits: Default::default(),
            warnings: Vec::new(),
            sequence: None,
            inserts: Vec::new(),
            folder: None,
        }
    }
}

/// The world point on the plane y = `y` seen through image position (`px`, `py`) in pixels.
pub fn point_on_plane(session: &Session, px: f32, py: f32, y: f32) -> Vec3 {
    let camera = &session.scene.cameras[0];
    let (w, h) = (session.output.width as f32, session.output.height as f32);
    let tan_half = (camera.yfov * 0.5).tan();
    let dir = Vec3::new((2.0 * px / w - 1.0) * tan_half * w / h, (1.0 - 2.0 * py / h) * tan_half, -1.0);
    let dir = camera.world_from_camera.transform_vector3(dir).normalize();
    let eye = camera.world_from_camera.transform_point3(Vec3::ZERO);
    eye + dir * ((y - eye.y) / dir.y)
}

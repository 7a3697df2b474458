//! URDF: one link, whose frame is the object frame, with an explicit `<inertial>` at the centre
//! of mass and the shape as collision and visual geometry: a box where the shape is one, else a
//! mesh file (Wavefront OBJ of the shape's faces) written beside the URDF. Written with
//! `urdf-rs`.

use super::Body;
use nalgebra::Vector3;

/// The URDF document of `body` (robot and link named `name`) and, when the shape is not a
/// box, the OBJ mesh it refers to as `mesh_file` (a path relative to the URDF's folder).
pub fn urdf(body: &Body, name: &str, mesh_file: &str) -> (String, Option<String>) {
    let xyz = |v: &Vector3<f64>| urdf_rs::Vec3([v.x, v.y, v.z]);
    let (geometry, origin, mesh) = match &body.box_fit {
        Some(b) => {
            let (roll, pitch, yaw) = b.rotation.euler_angles();
            (
                urdf_rs::Geometry::Box {
                    size: xyz(&(b.half_extents * 2.0)),
                },
                urdf_rs::Pose {
                    xyz: xyz(&b.centre),
                    rpy: urdf_rs::Vec3([roll, pitch, yaw]),
                },
                None,
            )
        }
        None => (
            urdf_rs::Geometry::Mesh {
                filename: mesh_file.to_string(),
                scale: None,
            },
            urdf_rs::Pose::default(),
            Some(obj(body)),
        ),
    };
    let i = &body.inertia;
    let link = urdf_rs::Link {
        name: name.to_string(),
        inertial: urdf_rs::Inertial {
            origin: urdf_rs::Pose {
                xyz: xyz(&body.com),
                rpy: urdf_rs::Vec3([0.0; 3]),
            },
            mass: urdf_rs::Mass {
                value: body.mass_kg,
            },
            inertia: urdf_rs::Inertia {
                ixx: i[(0, 0)],
                ixy: i[(0, 1)],
                ixz: i[(0, 2)],
                iyy: i[(1, 1)],
                iyz: i[(1, 2)],
                izz: i[(2, 2)],
            },
        },
        visual: vec![urdf_rs::Visual {
            name: Some(format!("{name}_shape")),
            origin: origin.clone(),
            geometry: geometry.clone(),
            material: None,
        }],
        collision: vec![urdf_rs::Collision {
            name: Some(format!("{name}_shape")),
            origin,
            geometry,
        }],
    };
    let robot = urdf_rs::Robot {
        name: name.to_string(),
        links: vec![link],
        joints: vec![],
        materials: vec![],
    };
    let mut text = String::from("<?xml version=\"1.0\"?>\n<!-- written by objmodel export:");
    for note in &body.notes {
        text += &format!("\n  {}", note.replace("--", "-"));
    }
    text += "\n-->\n";
    text += &urdf_rs::write_to_string(&robot).expect("a URDF of numbers and names");
    (text + "\n", mesh)
}

/// The shape as a Wavefront OBJ: its corners and each face's polygon (outward).
fn obj(body: &Body) -> String {
    let mut s = String::from("# the object's shape, learnt by objmodel (object frame, metres)\n");
    for v in &body.shape.vertices {
        s += &format!("v {} {} {}\n", v.x, v.y, v.z);
    }
    for f in &body.shape.faces {
        s += "f";
        for i in &f.polygon {
            s += &format!(" {}", i + 1);
        }
        s += "\n";
    }
    s
}

//! MuJoCo's MJCF: the object as the first body of the model, with a free joint; the body's own
//! frame is the object frame; its geometry is a box where the shape is one, else a mesh of the
//! shape's corners (MuJoCo collides with their convex hull); an explicit `<inertial>` at the
//! centre of mass with the mass and the full inertia. Written with `quick-xml`.

use super::Body;
use nalgebra::Vector3;
use quick_xml::events::{BytesDecl, BytesEnd, BytesStart, BytesText, Event};
use quick_xml::Writer;

fn numbers(x: &[f64]) -> String {
    x.iter()
        .map(|v| format!("{v}"))
        .collect::<Vec<_>>()
        .join(" ")
}

fn v3(v: &Vector3<f64>) -> String {
    numbers(v.as_slice())
}

/// The MJCF document of `body`, the model and body named `name`.
pub fn mjcf(body: &Body, name: &str) -> String {
    let mut w = Writer::new_with_indent(Vec::new(), b' ', 2);
    let write = |w: &mut Writer<Vec<u8>>, e: Event| w.write_event(e).expect("writing to memory");
    write(
        &mut w,
        Event::Decl(BytesDecl::new("1.0", Some("utf-8"), None)),
    );
    for note in std::iter::once("written by objmodel export: the object learnt from demonstrations")
        .chain(body.notes.iter().map(String::as_str))
    {
        write(
            &mut w,
            Event::Comment(BytesText::new(&format!(" {} ", note.replace("--", "-")))),
        );
    }
    write(
        &mut w,
        Event::Start(BytesStart::new("mujoco").with_attributes([("model", name)])),
    );
    write(
        &mut w,
        Event::Empty(BytesStart::new("compiler").with_attributes([("angle", "radian")])),
    );
    let mesh_name = format!("{name}_shape");
    if body.box_fit.is_none() {
        write(&mut w, Event::Start(BytesStart::new("asset")));
        let vertex: Vec<f64> = body
            .shape
            .vertices
            .iter()
            .flat_map(|v| [v.x, v.y, v.z])
            .collect();
        write(
            &mut w,
            Event::Empty(
                BytesStart::new("mesh")
                    .with_attributes([("name", mesh_name.as_str()), ("vertex", &numbers(&vertex))]),
            ),
        );
        write(&mut w, Event::End(BytesEnd::new("asset")));
    }
    write(&mut w, Event::Start(BytesStart::new("worldbody")));
    write(
        &mut w,
        Event::Start(BytesStart::new("body").with_attributes([("name", name), ("pos", "0 0 0")])),
    );
    let free = format!("{name}_free");
    write(
        &mut w,
        Event::Empty(BytesStart::new("freejoint").with_attributes([("name", free.as_str())])),
    );
    let i = &body.inertia;
    let full = numbers(&[
        i[(0, 0)],
        i[(1, 1)],
        i[(2, 2)],
        i[(0, 1)],
        i[(0, 2)],
        i[(1, 2)],
    ]);
    write(
        &mut w,
        Event::Empty(BytesStart::new("inertial").with_attributes([
            ("pos", v3(&body.com).as_str()),
            ("mass", &format!("{}", body.mass_kg)),
            ("fullinertia", &full),
        ])),
    );
    let friction = format!("{} 0.005 0.0001", body.friction);
    let geom = match &body.box_fit {
        Some(b) => {
            let q = b.rotation.quaternion();
            BytesStart::new("geom").with_attributes([
                ("name", mesh_name.as_str()),
                ("type", "box"),
                ("size", &v3(&b.half_extents)),
                ("pos", &v3(&b.centre)),
                ("quat", &numbers(&[q.w, q.i, q.j, q.k])),
                ("friction", &friction),
                // The inertial element above gives the mass properties; the geom only collides.
                ("mass", "0"),
            ])
        }
        None => BytesStart::new("geom").with_attributes([
            ("name", mesh_name.as_str()),
            ("type", "mesh"),
            ("mesh", &mesh_name),
            ("friction", &friction),
            ("mass", "0"),
        ]),
    };
    write(&mut w, Event::Empty(geom));
    write(&mut w, Event::End(BytesEnd::new("body")));
    write(&mut w, Event::End(BytesEnd::new("worldbody")));
    write(&mut w, Event::End(BytesEnd::new("mujoco")));
    String::from_utf8(w.into_inner()).expect("XML of UTF-8 text") + "\n"
}

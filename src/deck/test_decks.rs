//! Decks and models shared by the reader's and the writer's tests, and
//! helpers to edit a deck and check the error it gives.

use std::path::Path;

use super::{parse_deck, Deck};
use crate::error::{FlankError, Result};
use crate::fem::material::Material;
use crate::fem::mesh::{ElementKind, Mesh};
use crate::fem::model::{Dirichlet, Model, NodalForce, Pressure};

/// One C3D20 element using every supported keyword, with comments, mixed
/// case, a continued keyword line, GENERATE and a Fortran exponent.
pub(super) const HEX: &str = "\
** One C3D20 element: every supported keyword
*Heading
One hexahedron
*NODE, NSET=Nall
1, 0, 0, 0
2, 1., 0., 0.
3, 1, 1
4, 0, 1.0e0, 0,
5, 0, 0, 1
6, 1, 0, 1
7, 1, 1, 1
8, 0, 1, 1
9, 0.5, 0, 0
10, 1, 0.5, 0
11, 0.5, 1, 0
12, 0, 0.5, 0
13, 0.5, 0, 1
14, 1, 0.5, 1
15, 0.5, 1, 1
16, 0, 0.5, 1
17, 0, 0, 0.5
18, 1, 0, 0.5
19, 1, 1, 0.5
20, 0, 1, 5D-1
*Element, type=c3d20,
** comment inside a continued keyword line
 elset=Block
1, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15,
16, 17, 18, 19, 20
*NSET, NSET = bottom
1, 2, 3, 4, 9, 10, 11, 12
*nset,nset=TOP,generate
5, 8
13, 16, 1
*Nset, nset=Both
bottom, TOP
*ELSET,ELSET=E1,GENERATE
1,1
*MATERIAL, NAME=Steel
*ELASTIC
210000., 0.3
*DENSITY
7.85e-9
*SOLID SECTION, ELSET=BLOCK, MATERIAL=steel

*BOUNDARY
bottom, 1, 3
*STEP
*STATIC
*BOUNDARY
1, 1, 1, 0.0
top, 3, 3, -0.01
*CLOAD
7, 1, 100.5
*cload
7, 1, 1.5D1
*DLOAD
E1, P2, 5.0
*NODE PRINT, NSET=NALL
U
*EL PRINT, ELSET=EALL
S
*END STEP
";

/// One C3D15 wedge.
pub(super) const WEDGE: &str = "\
*NODE, NSET=NALL
1,0,0,0
2,1,0,0
3,0,1,0
4,0,0,1
5,1,0,1
6,0,1,1
7,.5,0,0
8,.5,.5,0
9,0,.5,0
10,.5,0,1
11,.5,.5,1
12,0,.5,1
13,0,0,.5
14,1,0,.5
15,0,1,.5
*ELEMENT,TYPE=C3D15,ELSET=W
1,1,2,3,4,5,6,7,8,9,10,
11,12,13,14,15
*MATERIAL,NAME=AL
*ELASTIC
70000,0.33
*SOLID SECTION,ELSET=W,MATERIAL=AL
*BOUNDARY
1,1,3
2,2,3
3,3
*STEP
*STATIC
*DLOAD
1,P5,2.5
*NODE PRINT, NSET=NALL
U
*END STEP
";

pub(super) fn parse(deck: &str) -> Result<Deck> {
    parse_deck(deck, Path::new("test.inp"))
}

/// 1-based line of the first line containing `needle`.
pub(super) fn line_of(deck: &str, needle: &str) -> usize {
    deck.lines()
        .position(|l| l.contains(needle))
        .unwrap_or_else(|| panic!("'{needle}' not in deck"))
        + 1
}

pub(super) fn with(deck: &str, from: &str, to: &str) -> String {
    assert!(deck.contains(from), "'{from}' not in deck");
    deck.replacen(from, to, 1)
}

/// Asserts a Parse error at `line` whose message contains `word`.
pub(super) fn expect_err(deck: &str, line: usize, word: &str) {
    match parse(deck) {
        Err(FlankError::Parse {
            line: l, message, ..
        }) => {
            assert_eq!(l, line, "wrong line for: {message}");
            assert!(
                message.to_lowercase().contains(&word.to_lowercase()),
                "'{word}' not in: {message}"
            );
        }
        other => panic!("expected a parse error, got {other:?}"),
    }
}

/// Node indices of the given labels.
pub(super) fn idx(mesh: &Mesh, labels: &[u64]) -> Vec<usize> {
    let mut v: Vec<usize> = labels.iter().map(|&l| mesh.node(l).unwrap()).collect();
    v.sort_unstable();
    v
}

/// Three elements of all kinds, two materials, sets, every load type.
pub(super) fn sample_model() -> Model {
    let mut mesh = Mesh::new();
    for i in 0..36u64 {
        let f = i as f64;
        let x = [
            f * 0.1,
            ((i * 7 % 13) as f64).sqrt() * 3.3,
            -f / 3.0 + (f * 0.7).sin() * 40.0,
        ];
        mesh.add_node(1000 + 3 * i, x).unwrap();
    }
    mesh.add_element(7, ElementKind::C3D20, (0..20).collect())
        .unwrap();
    mesh.add_element(3, ElementKind::C3D20R, (8..28).collect())
        .unwrap();
    mesh.add_element(100, ElementKind::C3D15, (21..36).collect())
        .unwrap();
    mesh.extend_node_set("FIX", [0, 1, 2, 3]);
    mesh.extend_element_set("HUB", [1]);
    let mut dirichlet = Vec::new();
    for node in 0..4 {
        for component in 0..3 {
            dirichlet.push(Dirichlet {
                node,
                component,
                value: 0.0,
            });
        }
    }
    dirichlet.push(Dirichlet {
        node: 30,
        component: 1,
        value: -0.0123,
    });
    Model {
        mesh,
        materials: vec![
            Material::new("steel", 210000.0, 0.3).unwrap(),
            Material::new("Bronze alloy", 1.1e5, 0.34).unwrap(),
        ],
        element_material: vec![0, 1, 0],
        dirichlet,
        forces: vec![
            NodalForce {
                node: 33,
                component: 2,
                value: 1234.5,
            },
            NodalForce {
                node: 33,
                component: 2,
                value: 0.1 + 0.2,
            },
        ],
        pressures: vec![
            Pressure {
                element: 0,
                face: 2,
                value: 1.5,
            },
            Pressure {
                element: 2,
                face: 5,
                value: -2.25,
            },
        ],
        body_loads: Vec::new(),
        temperatures: None,
        couplings: Vec::new(),
        equations: Vec::new(),
        contact: Default::default(),
    }
}

/// Two unit C3D20 cubes stacked in z (touching at z = 1), a contact pair
/// of the upper cube's bottom face (slave, element face) on the lower
/// cube's top face (master), hard contact; the upper cube is pushed down.
pub(super) fn two_cubes(contact: &str) -> String {
    let mut s = String::from("*NODE, NSET=NALL\n");
    for b in 0..2u64 {
        for (i, p) in crate::fem::element::HEX20_NODES.iter().enumerate() {
            let x = [
                0.5 * (p[0] + 1.0),
                0.5 * (p[1] + 1.0),
                0.5 * (p[2] + 1.0) + b as f64,
            ];
            s += &format!("{}, {}, {}, {}\n", 100 * b + i as u64 + 1, x[0], x[1], x[2]);
        }
    }
    s += "*ELEMENT, TYPE=C3D20, ELSET=EALL\n";
    for b in 0..2u64 {
        let n: Vec<String> = (1..=20).map(|i| (100 * b + i).to_string()).collect();
        s += &format!(
            "{}, {},\n{}\n",
            b + 1,
            n[..15].join(", "),
            n[15..].join(", ")
        );
    }
    s += "*ELSET, ELSET=UPPER\n2\n*NSET, NSET=UPPER_BOTTOM\n101, 102, 103, 104, 109, 110, 111, 112\n";
    s += "*NSET, NSET=BOT\n1, 2, 3, 4, 9, 10, 11, 12\n";
    s += "*NSET, NSET=TOP\n105, 106, 107, 108, 113, 114, 115, 116\n";
    s += "*MATERIAL, NAME=STEEL\n*ELASTIC\n210000., 0.3\n*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL\n";
    s += contact;
    s += "*BOUNDARY\nBOT, 1, 3\nTOP, 1, 2\n*STEP\n*STATIC\n*BOUNDARY\nTOP, 3, 3, -0.001\n*NODE PRINT, NSET=NALL\nU\n*CONTACT PRINT\nCSTR\n*END STEP\n";
    s
}

pub(super) const CONTACT: &str = "\
*SURFACE, NAME=SLAVE, TYPE=ELEMENT
UPPER, S1
*SURFACE, NAME=MASTER
1, S2
*SURFACE, NAME=NODES, TYPE=NODE
UPPER_BOTTOM
*SURFACE INTERACTION, NAME=SI
*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR
1e7, 0.001
*FRICTION
0.0
*SURFACE INTERACTION, NAME=HARD
*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=HARD
*CONTACT PAIR, INTERACTION=SI, TYPE=NODE TO SURFACE, SMALL SLIDING
SLAVE, MASTER
";

/// The unit cube of HEX, base clamped, its top face held by a rigid body
/// whose reference node 100 is fixed and whose rotation node 101 may
/// turn about z only, loaded by a moment.
pub(super) const RIGID: &str = "\
*NODE, NSET=NALL
1, 0, 0, 0
2, 1, 0, 0
3, 1, 1, 0
4, 0, 1, 0
5, 0, 0, 1
6, 1, 0, 1
7, 1, 1, 1
8, 0, 1, 1
9, 0.5, 0, 0
10, 1, 0.5, 0
11, 0.5, 1, 0
12, 0, 0.5, 0
13, 0.5, 0, 1
14, 1, 0.5, 1
15, 0.5, 1, 1
16, 0, 0.5, 1
17, 0, 0, 0.5
18, 1, 0, 0.5
19, 1, 1, 0.5
20, 0, 1, 0.5
*NODE
100, 0.5, 0.5, 1.25
101, 0.5, 0.5, 1.25
*ELEMENT, TYPE=C3D20, ELSET=EALL
1, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15,
16, 17, 18, 19, 20
*NSET, NSET=BASE
1, 2, 3, 4, 9, 10, 11, 12
*NSET, NSET=TOP
5, 6, 7, 8, 13, 14, 15, 16
*NSET, NSET=REFS
100, 101
*MATERIAL, NAME=STEEL
*ELASTIC
210000., 0.3
*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL
*RIGID BODY, NSET=TOP, REF NODE=100, ROT NODE=101
*STEP
*STATIC
*BOUNDARY
BASE, 1, 3
100, 1, 3
101, 1, 2
*CLOAD
101, 3, 1000.
*NODE PRINT, NSET=NALL
U
*END STEP
";

/// RIGID with the rigid body replaced by *COUPLING + *KINEMATIC on the
/// top face; the rotations are DOFs 4-6 of the reference node.
pub(super) fn coupling_deck() -> String {
    let d = with(
        RIGID,
        "*RIGID BODY, NSET=TOP, REF NODE=100, ROT NODE=101\n",
        "*SURFACE, NAME=STOP, TYPE=ELEMENT\n1, S2\n*COUPLING, REF NODE=100, SURFACE=STOP, CONSTRAINT NAME=HUB\n*KINEMATIC\n1, 3\n",
    );
    let d = with(&d, "100, 1, 3\n101, 1, 2\n", "100, 1, 5\n");
    let d = with(&d, "101, 0.5, 0.5, 1.25\n", "");
    let d = with(&d, "100, 101\n", "100\n");
    with(&d, "101, 3, 1000.", "100, 6, 1000.")
}

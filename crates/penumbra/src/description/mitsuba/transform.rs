//! Mitsuba's `<transform>`: affine 4 × 4 matrices in double precision,
//! row-major, acting on column vectors. Each operation of a transform is
//! applied after the ones before it: `M = op · M`.

/// A 4 × 4 matrix, `m[row][column]`.
pub type Mat4 = [[f64; 4]; 4];

pub const IDENTITY: Mat4 = [
    [1.0, 0.0, 0.0, 0.0],
    [0.0, 1.0, 0.0, 0.0],
    [0.0, 0.0, 1.0, 0.0],
    [0.0, 0.0, 0.0, 1.0],
];

/// `a · b`.
pub fn mul(a: &Mat4, b: &Mat4) -> Mat4 {
    let mut m = [[0.0; 4]; 4];
    for (i, row) in m.iter_mut().enumerate() {
        for (j, x) in row.iter_mut().enumerate() {
            *x = (0..4).map(|k| a[i][k] * b[k][j]).sum();
        }
    }
    m
}

pub fn translate(v: [f64; 3]) -> Mat4 {
    let mut m = IDENTITY;
    for i in 0..3 {
        m[i][3] = v[i];
    }
    m
}

pub fn scale(v: [f64; 3]) -> Mat4 {
    let mut m = IDENTITY;
    for i in 0..3 {
        m[i][i] = v[i];
    }
    m
}

/// A right-handed rotation by `degrees` about `axis` (not zero).
pub fn rotate(axis: [f64; 3], degrees: f64) -> Mat4 {
    let [x, y, z] = normalize(axis);
    let (s, c) = degrees.to_radians().sin_cos();
    let t = 1.0 - c;
    [
        [t * x * x + c, t * x * y - s * z, t * x * z + s * y, 0.0],
        [t * x * y + s * z, t * y * y + c, t * y * z - s * x, 0.0],
        [t * x * z - s * y, t * y * z + s * x, t * z * z + c, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ]
}

/// The camera-to-world matrix of an eye at `origin` looking at `target`:
/// local +z along the view, +y the part of `up` across it, +x to the left
/// (`up × dir`). `None` when the view or `up` is degenerate.
pub fn look_at(origin: [f64; 3], target: [f64; 3], up: [f64; 3]) -> Option<Mat4> {
    let dir = normalize(sub(target, origin));
    let left = normalize(cross(up, dir));
    let new_up = cross(dir, left);
    let m = [
        [left[0], new_up[0], dir[0], origin[0]],
        [left[1], new_up[1], dir[1], origin[1]],
        [left[2], new_up[2], dir[2], origin[2]],
        [0.0, 0.0, 0.0, 1.0],
    ];
    m.iter().flatten().all(|x| x.is_finite()).then_some(m)
}

/// A point through `m`.
pub fn point(m: &Mat4, p: [f64; 3]) -> [f64; 3] {
    [0, 1, 2].map(|i| m[i][0] * p[0] + m[i][1] * p[1] + m[i][2] * p[2] + m[i][3])
}

/// A direction through `m`.
pub fn vector(m: &Mat4, v: [f64; 3]) -> [f64; 3] {
    [0, 1, 2].map(|i| m[i][0] * v[0] + m[i][1] * v[1] + m[i][2] * v[2])
}

/// The determinant of the upper-left 3 × 3 block.
pub fn det3(m: &Mat4) -> f64 {
    m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
        - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
        + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
}

/// Whether the linear part collapses a dimension (relative to the size of
/// its entries) or the matrix holds a non-finite number.
pub fn is_singular(m: &Mat4) -> bool {
    let size = (0..3)
        .flat_map(|i| (0..3).map(move |j| (i, j)))
        .map(|(i, j)| m[i][j].abs())
        .fold(0.0, f64::max);
    let det = det3(m);
    !det.is_finite() || size == 0.0 || det.abs() <= 1e-12 * size * size * size
}

/// Whether the last row is `0 0 0 1`.
pub fn is_affine(m: &Mat4) -> bool {
    m[3] == [0.0, 0.0, 0.0, 1.0]
}

pub fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

pub fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

pub fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

pub fn length(v: [f64; 3]) -> f64 {
    dot(v, v).sqrt()
}

/// `v` of length 1 (NaNs for the zero vector).
pub fn normalize(v: [f64; 3]) -> [f64; 3] {
    let l = length(v);
    v.map(|x| x / l)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: &Mat4, b: &Mat4) -> bool {
        a.iter()
            .flatten()
            .zip(b.iter().flatten())
            .all(|(x, y)| (x - y).abs() < 1e-12)
    }

    #[test]
    fn rotations_turn_the_axes_right_handed() {
        let z90 = rotate([0.0, 0.0, 1.0], 90.0);
        let x = point(&z90, [1.0, 0.0, 0.0]);
        assert!((x[0]).abs() < 1e-15 && (x[1] - 1.0).abs() < 1e-15, "{x:?}");
        let x90 = rotate([2.0, 0.0, 0.0], 90.0);
        let y = vector(&x90, [0.0, 1.0, 0.0]);
        assert!((y[2] - 1.0).abs() < 1e-15, "{y:?}");
    }

    #[test]
    fn operations_compose_each_after_the_last() {
        // scale 2, then translate (1, 0, 0): a point at x = 1 goes to 3.
        let m = mul(
            &translate([1.0, 0.0, 0.0]),
            &mul(&scale([2.0; 3]), &IDENTITY),
        );
        assert_eq!(point(&m, [1.0, 0.0, 0.0]), [3.0, 0.0, 0.0]);
        let by_hand = [
            [2.0, 0.0, 0.0, 1.0],
            [0.0, 2.0, 0.0, 0.0],
            [0.0, 0.0, 2.0, 0.0],
            [0.0, 0.0, 0.0, 1.0],
        ];
        assert!(close(&m, &by_hand));
    }

    #[test]
    fn look_at_puts_the_view_on_z_and_up_on_y() {
        let m = look_at([0.0, 1.0, 5.0], [0.0, 1.0, 0.0], [0.0, 1.0, 0.0]).unwrap();
        let by_hand = [
            [-1.0, 0.0, 0.0, 0.0],
            [0.0, 1.0, 0.0, 1.0],
            [0.0, 0.0, -1.0, 5.0],
            [0.0, 0.0, 0.0, 1.0],
        ];
        assert!(close(&m, &by_hand), "{m:?}");
        assert!(det3(&m) > 0.0);
        assert!(look_at([0.0; 3], [0.0, 1.0, 0.0], [0.0, 1.0, 0.0]).is_none());
        assert!(look_at([0.0; 3], [0.0; 3], [0.0, 1.0, 0.0]).is_none());
    }

    #[test]
    fn singular_and_projective_matrices_are_told_apart() {
        assert!(is_singular(&scale([1.0, 0.0, 1.0])));
        assert!(!is_singular(&scale([1e-9, 1e-9, 1e-9])));
        assert!(!is_singular(&rotate([1.0, 1.0, 0.0], 30.0)));
        let mut p = IDENTITY;
        p[3][2] = 1.0;
        assert!(!is_affine(&p));
    }
}

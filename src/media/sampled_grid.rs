//! A grid of values over the unit cube, looked up with trilinear
//! interpolation between sample points at the cell centres (pbrt-v4's
//! `SampledGrid`); outside the grid the samples are zero.

use glam::Vec3;

#[derive(Clone, Debug)]
pub struct SampledGrid<T> {
    values: Vec<T>,
    n: [i32; 3],
}

impl<T: Copy + Default> SampledGrid<T> {
    /// `values` in x-fastest order, `nx·ny·nz` of them (checked by the
    /// caller).
    pub fn new(values: Vec<T>, nx: i32, ny: i32, nz: i32) -> Self {
        SampledGrid {
            values,
            n: [nx, ny, nz],
        }
    }

    pub fn values(&self) -> &[T] {
        &self.values
    }

    fn at(&self, x: i32, y: i32, z: i32) -> T {
        let [nx, ny, nz] = self.n;
        if x < 0 || y < 0 || z < 0 || x >= nx || y >= ny || z >= nz {
            return T::default();
        }
        self.values[((z * ny + y) * nx + x) as usize]
    }

    /// The interpolated value at `p` (0…1 per axis), through `eval` (which
    /// turns a stored value into what is interpolated).
    pub fn lookup<U>(&self, p: Vec3, eval: impl Fn(T) -> U) -> U
    where
        U: std::ops::Mul<f32, Output = U> + std::ops::Add<Output = U>,
    {
        let s = Vec3::new(
            p.x * self.n[0] as f32 - 0.5,
            p.y * self.n[1] as f32 - 0.5,
            p.z * self.n[2] as f32 - 0.5,
        );
        let i = s.floor();
        let d = s - i;
        let (x, y, z) = (i.x as i32, i.y as i32, i.z as i32);
        let v = |dx: i32, dy: i32, dz: i32| eval(self.at(x + dx, y + dy, z + dz));
        let lerp = |t: f32, a: U, b: U| a * (1.0 - t) + b * t;
        let y0 = lerp(
            d.y,
            lerp(d.x, v(0, 0, 0), v(1, 0, 0)),
            lerp(d.x, v(0, 1, 0), v(1, 1, 0)),
        );
        let y1 = lerp(
            d.y,
            lerp(d.x, v(0, 0, 1), v(1, 0, 1)),
            lerp(d.x, v(0, 1, 1), v(1, 1, 1)),
        );
        lerp(d.z, y0, y1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn trilinear_between_cell_centres() {
        // Two cells along x: centres at 0.25 and 0.75.
        let g = SampledGrid::new(vec![1.0f32, 3.0], 2, 1, 1);
        let f = |p: Vec3| g.lookup(p, |v| v);
        assert!((f(Vec3::new(0.25, 0.5, 0.5)) - 1.0).abs() < 1e-6);
        assert!((f(Vec3::new(0.75, 0.5, 0.5)) - 3.0).abs() < 1e-6);
        assert!((f(Vec3::new(0.5, 0.5, 0.5)) - 2.0).abs() < 1e-6);
        // Towards the faces the samples fade to the zero outside.
        assert!((f(Vec3::new(0.0, 0.5, 0.5)) - 0.5).abs() < 1e-6);
    }
}

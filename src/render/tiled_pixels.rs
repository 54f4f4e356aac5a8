//! The render loop's pixel accumulators, stored tile by tile: each tile's
//! pixels are one contiguous run of the array (row-major within the
//! tile), so every render task owns a slice of it and the film needs no
//! second copy to hand tiles out. Readers see the pixels in image rows.

use glam::IVec2;

/// Tile edge in pixels (tiles at the right and bottom edges may be
/// narrower or shorter).
const TILE: i32 = 16;

/// A tile: pixels `[lo, hi)` in x and y.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Tile {
    pub lo: IVec2,
    pub hi: IVec2,
}

impl Tile {
    pub fn pixel_count(&self) -> usize {
        let size = self.hi - self.lo;
        (size.x * size.y) as usize
    }
}

/// One accumulator per pixel of `bounds`, laid out tile after tile (tiles
/// in rows of tiles, top to bottom, left to right).
pub struct TiledPixels<P> {
    bounds: (IVec2, IVec2),
    pixels: Vec<P>,
}

impl<P: Clone> TiledPixels<P> {
    /// Every pixel of `bounds` starting as `empty`.
    pub fn new(bounds: (IVec2, IVec2), empty: P) -> Self {
        let size = (bounds.1 - bounds.0).max(IVec2::ZERO);
        TiledPixels {
            bounds,
            pixels: vec![empty; (size.x * size.y) as usize],
        }
    }
}

impl<P> TiledPixels<P> {
    /// No pixels (what is left once they are made into an image).
    pub fn empty() -> Self {
        TiledPixels {
            bounds: (IVec2::ZERO, IVec2::ZERO),
            pixels: Vec::new(),
        }
    }

    pub fn len(&self) -> usize {
        self.pixels.len()
    }

    pub fn is_empty(&self) -> bool {
        self.pixels.is_empty()
    }

    /// The tiles in storage order.
    fn tiles(&self) -> Vec<Tile> {
        let (lo, hi) = self.bounds;
        (lo.y..hi.y)
            .step_by(TILE as usize)
            .flat_map(|y| {
                (lo.x..hi.x).step_by(TILE as usize).map(move |x| {
                    let tile_lo = IVec2::new(x, y);
                    Tile {
                        lo: tile_lo,
                        hi: (tile_lo + IVec2::splat(TILE)).min(hi),
                    }
                })
            })
            .collect()
    }

    /// Each tile (in [`TiledPixels::tiles`]' order) with its pixels.
    pub fn tiles_mut(&mut self) -> Vec<(Tile, &mut [P])> {
        let tiles = self.tiles();
        let mut rest = self.pixels.as_mut_slice();
        let mut out = Vec::with_capacity(tiles.len());
        for tile in tiles {
            let (mine, after) = rest.split_at_mut(tile.pixel_count());
            out.push((tile, mine));
            rest = after;
        }
        out
    }

    /// Where pixel `p` (inside the bounds) is stored: the rows of tiles
    /// above it, the tiles left of it in its row of tiles (all as tall as
    /// its own), then its place in its tile.
    fn index(&self, p: IVec2) -> usize {
        let (lo, hi) = self.bounds;
        let width = hi.x - lo.x;
        let local = p - lo;
        let tile = local / TILE;
        let tile_lo = tile * TILE;
        let tile_height = TILE.min(hi.y - lo.y - tile_lo.y);
        let tile_width = TILE.min(width - tile_lo.x);
        let within = local - tile_lo;
        (tile_lo.y * width + tile_lo.x * tile_height + within.y * tile_width + within.x) as usize
    }

    /// The pixels in image order: rows top to bottom, each left to right.
    pub fn in_rows(&self) -> impl Iterator<Item = &P> + '_ {
        let (lo, hi) = self.bounds;
        (lo.y..hi.y).flat_map(move |y| {
            (lo.x..hi.x).map(move |x| &self.pixels[self.index(IVec2::new(x, y))])
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every pixel of bounds whose edges are not multiples of the tile
    /// size is stored once, in its tile's run, and read back in row order.
    #[test]
    fn tiles_cover_every_pixel_once_and_rows_read_back() {
        for bounds in [
            (IVec2::new(3, 5), IVec2::new(70, 41)),
            (IVec2::ZERO, IVec2::new(16, 16)),
            (IVec2::new(-7, 2), IVec2::new(-6, 40)),
            (IVec2::ZERO, IVec2::new(33, 1)),
        ] {
            let mut pixels = TiledPixels::new(bounds, IVec2::splat(i32::MIN));
            for (tile, slice) in pixels.tiles_mut() {
                assert_eq!(slice.len(), tile.pixel_count());
                let mut k = 0;
                for y in tile.lo.y..tile.hi.y {
                    for x in tile.lo.x..tile.hi.x {
                        slice[k] = IVec2::new(x, y);
                        k += 1;
                    }
                }
            }
            let (lo, hi) = bounds;
            let expected: Vec<IVec2> = (lo.y..hi.y)
                .flat_map(|y| (lo.x..hi.x).map(move |x| IVec2::new(x, y)))
                .collect();
            let read: Vec<IVec2> = pixels.in_rows().copied().collect();
            assert_eq!(read, expected, "{bounds:?}");
        }
    }

    #[test]
    fn empty_bounds_have_no_tiles() {
        let mut pixels = TiledPixels::new((IVec2::new(4, 4), IVec2::new(4, 9)), 0u8);
        assert!(pixels.is_empty());
        assert!(pixels.tiles_mut().is_empty());
        assert_eq!(pixels.in_rows().count(), 0);
    }
}

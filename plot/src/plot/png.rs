//! PNG files: a figure drawn by plotters' bitmap backend into an RGB buffer, encoded by `image`.

use std::path::Path;

use plotters::prelude::*;

use super::{Figure, PlotError};

/// Draws `fig` at its own size on white and writes it to `path` as an 8-bit RGB PNG.
pub fn save_png<F: Figure + ?Sized>(fig: &F, path: &Path) -> Result<(), PlotError> {
    let (w, h) = fig.size();
    let mut rgb = vec![0u8; w as usize * h as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, (w, h)).into_drawing_area();
        root.fill(&WHITE)?;
        fig.draw(&root)?;
        root.present()?;
    }
    image::save_buffer_with_format(
        path,
        &rgb,
        w,
        h,
        image::ExtendedColorType::Rgb8,
        image::ImageFormat::Png,
    )
    .map_err(|e| PlotError(format!("{}: {e}", path.display())))
}

#[cfg(test)]
mod tests {
    use super::*;
    use plotters::coord::Shift;

    /// A 40×20 figure: white, with a red square in its top-left quarter.
    struct Square;

    impl Figure for Square {
        fn size(&self) -> (u32, u32) {
            (40, 20)
        }
        fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
            root.draw(&Rectangle::new([(0, 0), (9, 9)], RED.filled()))?;
            Ok(())
        }
    }

    #[test]
    fn the_png_holds_the_drawn_pixels() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("square.png");
        save_png(&Square, &path).unwrap();
        let img = image::open(&path).unwrap().to_rgb8();
        assert_eq!(img.dimensions(), (40, 20));
        assert_eq!(img.get_pixel(5, 5).0, [255, 0, 0]);
        assert_eq!(img.get_pixel(30, 15).0, [255, 255, 255]);
    }
}

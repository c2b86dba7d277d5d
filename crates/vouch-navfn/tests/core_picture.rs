//! The plan picture: decodes as a PNG of the expected size, obstacles black, the path red,
//! start green and goal blue where the cells are.

use vouch_navfn::core::{COST_OBS, Cell, NoObserver};
use vouch_navfn::picture::{PictureInput, cell_scale, render, write_png};
use vouch_navfn::suite::CaseRunner;

#[test]
fn picture_shows_map_path_and_end_points() {
    let (nx, ny) = (12, 8);
    let mut map = vec![50u8; nx * ny];
    for y in 0..ny {
        for x in 0..nx {
            if x == 0 || y == 0 || x == nx - 1 || y == ny - 1 || (x == 6 && y < 5) {
                map[y * nx + x] = COST_OBS;
            }
        }
    }
    let mut r = CaseRunner::new();
    let o = r.run_paper(&map, nx, ny, Cell::new(2, 2), Cell::new(9, 2), &mut NoObserver).unwrap();
    assert!(o.len > 0);
    let pic = PictureInput::of(r.nav(), false);
    let img = render(&pic);
    let s = cell_scale(nx, ny);
    assert_eq!((img.width, img.height), (nx * s, ny * s));
    let px = |x: usize, y: usize| {
        let i = 3 * (y * img.width + x);
        [img.data[i], img.data[i + 1], img.data[i + 2]]
    };
    let centre = |c: usize| c * s + s / 2;
    assert_eq!(px(centre(6), centre(1)), [0, 0, 0], "wall cell is black");
    assert_eq!(px(centre(2), centre(2)), [20, 200, 60], "start marker green");
    assert_eq!(px(centre(9), centre(2)), [30, 90, 255], "goal marker blue");
    let red = img.data.chunks(3).filter(|p| *p == [230, 20, 20]).count();
    assert!(red > 10 * s, "path drawn ({red} red pixels)");
    let mut bytes = Vec::new();
    write_png(&mut bytes, &img).unwrap();
    let decoder = png::Decoder::new(std::io::Cursor::new(bytes.as_slice()));
    let reader = decoder.read_info().unwrap();
    assert_eq!(reader.info().width as usize, img.width);
}

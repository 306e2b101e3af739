//! `dynarole show`: a picture of a configuration (`show/picture.rs`: SVG, or PNG rasterised
//! from it), written to the file named.

mod picture;

use crate::load::Failure;
use crate::world::read_configuration;
pub use picture::render_svg;
use std::path::Path;
use std::process::ExitCode;

/// What `show` was asked to do: its command line, parsed once.
#[derive(clap::Args)]
pub struct ShowArgs {
    /// The configuration to draw (JSON).
    pub config: std::path::PathBuf,
    /// The picture to write: FILE.svg or FILE.png.
    #[arg(short = 'o', long = "output", value_name = "FILE")]
    pub output: std::path::PathBuf,
}

pub fn run(args: &ShowArgs) -> Result<ExitCode, Failure> {
    draw(&args.config, &args.output)
}

fn draw(config_path: &Path, output: &Path) -> Result<ExitCode, Failure> {
    let config = read_configuration(config_path)?;
    let svg = render_svg(&config)
        .map_err(|e| Failure::Input(format!("cannot draw {}: {e}", config_path.display())))?;
    let extension = output.extension().and_then(|e| e.to_str()).unwrap_or("");
    let bytes = match extension {
        "svg" => svg.into_bytes(),
        "png" => dynarole_campaign::rasterise_svg(&svg)
            .map_err(|e| Failure::Input(format!("cannot make {}: {e}", output.display())))?,
        _ => {
            return Err(Failure::Usage(format!(
                "{}: the picture must be a .svg or .png file",
                output.display()
            )))
        }
    };
    let cannot_write =
        |e: std::io::Error| Failure::Input(format!("cannot write {}: {e}", output.display()));
    // Like `compile -o` and `campaign -o`, the folder is made when it is missing.
    if let Some(parent) = output.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(parent).map_err(cannot_write)?;
    }
    std::fs::write(output, bytes).map_err(cannot_write)?;
    println!("wrote {}", output.display());
    Ok(ExitCode::SUCCESS)
}

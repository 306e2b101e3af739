//! Builds what `--firmware avr` runs: the module image (the generated C plus `runtime/avr`,
//! with avr-gcc) and the emulated board (`runtime/avr/emu` linked with simavr), each with
//! `runtime/avr/Makefile` (and the MCU options of `runtime/dr_mcu.mk`, the warning flags of
//! `runtime/dr_warn.mk`) so that its flags are defined once. Both are cached under the
//! simulator's cache root, keyed by a hash of every input, built in a temporary directory and
//! renamed into place.

use crate::build::{cache_root, publish};
use std::path::{Path, PathBuf};
use std::process::Command;

/// `runtime/avr` and the MCU options and warning flags it includes, embedded so that a build
/// needs only the AVR toolchain and simavr.
const SOURCES: [(&str, &str); 8] = [
    ("dr_mcu.mk", include_str!("../../../../runtime/dr_mcu.mk")),
    ("dr_warn.mk", include_str!("../../../../runtime/dr_warn.mk")),
    (
        "avr/Makefile",
        include_str!("../../../../runtime/avr/Makefile"),
    ),
    (
        "avr/dr_avr.c",
        include_str!("../../../../runtime/avr/dr_avr.c"),
    ),
    (
        "avr/dr_avr_board.h",
        include_str!("../../../../runtime/avr/dr_avr_board.h"),
    ),
    (
        "avr/emu/dr_avr_emu.c",
        include_str!("../../../../runtime/avr/emu/dr_avr_emu.c"),
    ),
    (
        "avr/emu/dr_avr_emu.h",
        include_str!("../../../../runtime/avr/emu/dr_avr_emu.h"),
    ),
    (
        "avr/emu/tests/test_emu.c",
        include_str!("../../../../runtime/avr/emu/tests/test_emu.c"),
    ),
];

/// `runtime/nesc`: the stand-ins for TinyOS the nesC component is compiled against.
const NESC_SOURCES: [(&str, &str); 13] = [
    (
        "nesc/Boot.nc",
        include_str!("../../../../runtime/nesc/Boot.nc"),
    ),
    (
        "nesc/Clock.nc",
        include_str!("../../../../runtime/nesc/Clock.nc"),
    ),
    (
        "nesc/DrMainP.nc",
        include_str!("../../../../runtime/nesc/DrMainP.nc"),
    ),
    (
        "nesc/MainC.nc",
        include_str!("../../../../runtime/nesc/MainC.nc"),
    ),
    (
        "nesc/Makefile",
        include_str!("../../../../runtime/nesc/Makefile"),
    ),
    (
        "nesc/Scheduler.nc",
        include_str!("../../../../runtime/nesc/Scheduler.nc"),
    ),
    (
        "nesc/TaskBasic.nc",
        include_str!("../../../../runtime/nesc/TaskBasic.nc"),
    ),
    (
        "nesc/Timer.nc",
        include_str!("../../../../runtime/nesc/Timer.nc"),
    ),
    (
        "nesc/TimerMilliC.nc",
        include_str!("../../../../runtime/nesc/TimerMilliC.nc"),
    ),
    (
        "nesc/TimerMilliP.nc",
        include_str!("../../../../runtime/nesc/TimerMilliP.nc"),
    ),
    (
        "nesc/TinySchedulerC.nc",
        include_str!("../../../../runtime/nesc/TinySchedulerC.nc"),
    ),
    (
        "nesc/dr_nesc.h",
        include_str!("../../../../runtime/nesc/dr_nesc.h"),
    ),
    (
        "nesc/dr_nesc_platform.h",
        include_str!("../../../../runtime/nesc/dr_nesc_platform.h"),
    ),
];

/// The nesC compiler's version the nesC build needs (Debian's 1.3.5 crashes).
const NESC_VERSION: &str = "1.4.0";

/// A built firmware image and its footprint.
#[derive(Clone, Debug)]
pub struct Image {
    pub elf: PathBuf,
    /// Code and constant data in flash (.text), initialised data (.data, in flash and RAM),
    /// zeroed data (.bss).
    pub text: u64,
    pub data: u64,
    pub bss: u64,
}

/// nesC 1.4.0's `nescc`: `NESCC`, else the one `scripts/ensure-nesc` builds (in
/// `$XDG_CACHE_HOME` or `~/.cache`, `dynarole/nesc-1.4.0`), else `nescc` on the PATH; the
/// first that says it is 1.4.0.
pub fn nescc() -> Result<PathBuf, String> {
    let cache = std::env::var_os("XDG_CACHE_HOME")
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".cache")));
    let candidates = std::env::var_os("NESCC")
        .map(PathBuf::from)
        .into_iter()
        .chain(cache.map(|c| c.join(format!("dynarole/nesc-{NESC_VERSION}/bin/nescc"))))
        .chain([PathBuf::from("nescc")]);
    for candidate in candidates {
        let version = Command::new(&candidate).arg("--version").output();
        if version.is_ok_and(|o| String::from_utf8_lossy(&o.stdout).contains(NESC_VERSION)) {
            return Ok(candidate);
        }
    }
    Err(format!(
        "--firmware avr-nesc needs nesC {NESC_VERSION}'s nescc (scripts/ensure-nesc builds it; NESCC=path names another)"
    ))
}

/// Says which tool is missing, and how to get it.
pub fn check_tools(source: super::FirmwareSource) -> Result<(), String> {
    if source == super::FirmwareSource::Nesc {
        nescc()?;
    }
    let works = |program: &str, args: &[&str]| {
        Command::new(program)
            .args(args)
            .output()
            .is_ok_and(|o| o.status.success())
    };
    if !works("avr-gcc", &["--version"]) || !works("avr-size", &["--version"]) {
        return Err(
            "--firmware avr needs avr-gcc and avr-libc (scripts/ensure-avr installs them)".into(),
        );
    }
    if !works("pkg-config", &["--exists", "simavr"]) {
        return Err("--firmware avr needs simavr's library and headers (libsimavr-dev, libelf-dev, pkg-config; scripts/ensure-avr installs them)".into());
    }
    Ok(())
}

/// The image of the generated program `files` with `defines` (-D flags).
pub fn image(files: &[(String, String)], defines: &[String]) -> Result<Image, String> {
    let mut inputs: Vec<(&str, &str)> = files
        .iter()
        .map(|(n, t)| (n.as_str(), t.as_str()))
        .collect();
    let joined = defines.join(" ");
    inputs.push(("defines", &joined));
    let directory = cached("avr-image", &inputs, "out/firmware.elf", |dir| {
        for (name, text) in files {
            write(&dir.join("program").join(name), text)?;
        }
        make(
            dir,
            &[
                "image",
                "PROGRAM=../program",
                "BUILD=../out",
                &format!("DEFINES={joined}"),
            ],
        )
    })?;
    built(&directory)
}

/// The image of the nesC component `nesc` around the generated program `files`, with
/// `defines` (runtime/avr's `make nesc-image`).
pub fn nesc_image(
    files: &[(String, String)],
    nesc: &[(String, String)],
    defines: &[String],
) -> Result<Image, String> {
    let nescc = nescc()?;
    let nescc = nescc.to_string_lossy().into_owned();
    let joined = defines.join(" ");
    let mut inputs: Vec<(&str, &str)> = files
        .iter()
        .chain(nesc)
        .map(|(n, t)| (n.as_str(), t.as_str()))
        .chain(NESC_SOURCES)
        .collect();
    inputs.push(("defines", &joined));
    inputs.push(("nescc", &nescc));
    let directory = cached("avr-nesc-image", &inputs, "out/firmware.elf", |dir| {
        for (name, text) in files.iter().chain(nesc) {
            write(&dir.join("program").join(name), text)?;
        }
        for (name, text) in NESC_SOURCES {
            write(&dir.join(name), text)?;
        }
        make(
            dir,
            &[
                "nesc-image",
                "PROGRAM=../program",
                "BUILD=../out",
                "NESC=../nesc",
                &format!("NESCC={nescc}"),
                &format!("DEFINES={joined}"),
            ],
        )
    })?;
    built(&directory)
}

/// The emulated board's shared library.
pub fn emulator() -> Result<PathBuf, String> {
    let flags = Command::new("pkg-config")
        .args(["--cflags", "--libs", "simavr"])
        .output()
        .map(|o| String::from_utf8_lossy(&o.stdout).into_owned())
        .unwrap_or_default();
    let directory = cached(
        "avr-emu",
        &[("pkg-config", &flags)],
        "out/libdravemu.so",
        |dir| make(dir, &["emu-lib", "BUILD=../out"]),
    )?;
    Ok(directory.join("out/libdravemu.so"))
}

fn write(path: &Path, text: &str) -> Result<(), String> {
    if let Some(parent) = path.parent() {
        std::fs::create_dir_all(parent)
            .map_err(|e| format!("cannot create {}: {e}", parent.display()))?;
    }
    std::fs::write(path, text).map_err(|e| format!("cannot write {}: {e}", path.display()))
}

fn make(dir: &Path, args: &[&str]) -> Result<(), String> {
    let output = Command::new("make")
        .arg("-s")
        .arg("-C")
        .arg(dir.join("avr"))
        .args(args)
        .output()
        .map_err(|e| format!("cannot run make: {e}"))?;
    if output.status.success() {
        Ok(())
    } else {
        Err(format!(
            "building the AVR firmware in {} failed:\n{}{}",
            dir.display(),
            String::from_utf8_lossy(&output.stdout),
            String::from_utf8_lossy(&output.stderr)
        ))
    }
}

/// text, data and bss of an ELF image (`avr-size`, Berkeley format).
fn sizes(elf: &Path) -> Result<(u64, u64, u64), String> {
    let output = Command::new("avr-size")
        .arg(elf)
        .output()
        .map_err(|e| format!("cannot run avr-size: {e}"))?;
    let text = String::from_utf8_lossy(&output.stdout);
    let numbers: Vec<u64> = text
        .lines()
        .nth(1)
        .unwrap_or("")
        .split_whitespace()
        .take(3)
        .filter_map(|w| w.parse().ok())
        .collect();
    match numbers[..] {
        [t, d, b] => Ok((t, d, b)),
        _ => Err(format!(
            "avr-size gave no sizes for {}: {text}",
            elf.display()
        )),
    }
}

/// FNV-1a (64 bits) over `runtime/avr` and `inputs`.
fn key(inputs: &[(&str, &str)]) -> u64 {
    let mut hash: u64 = 0xcbf2_9ce4_8422_2325;
    for (name, text) in SOURCES.iter().chain(inputs) {
        for b in name.bytes().chain([0]).chain(text.bytes()).chain([0]) {
            hash ^= u64::from(b);
            hash = hash.wrapping_mul(0x0100_0000_01b3);
        }
    }
    hash
}

/// The cache directory holding `product` for `inputs`, built by `build` (which gets a
/// directory holding `avr/`, runtime/avr) when missing; published as the simulator's builds
/// are, so that processes building it at once never see it half made.
fn cached(
    prefix: &str,
    inputs: &[(&str, &str)],
    product: &str,
    build: impl FnOnce(&Path) -> Result<(), String>,
) -> Result<PathBuf, String> {
    let directory = cache_root().join(format!("{prefix}-{:016x}", key(inputs)));
    if !directory.join(product).is_file() {
        publish(&directory, product, |temp| {
            SOURCES
                .iter()
                .try_for_each(|(name, text)| write(&temp.join(name), text))?;
            build(temp)
        })?;
    }
    Ok(directory)
}

/// The image a cached build folder holds, with its sizes.
fn built(directory: &Path) -> Result<Image, String> {
    let elf = directory.join("out/firmware.elf");
    let (text, data, bss) = sizes(&elf)?;
    Ok(Image {
        elf,
        text,
        data,
        bss,
    })
}

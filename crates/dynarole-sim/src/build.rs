//! From generated C to a loaded shared library: the output directory plus the simulator's
//! platform (`runtime/sim/dr_sim.c`) compiled with the system `cc` into a cache directory
//! keyed by a hash of everything that goes into the build, then loaded with libloading.

use crate::describe::DescribeFn;
use crate::ffi;
use std::ffi::c_void;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;

/// The simulator's platform, embedded so that a build needs nothing but `cc`.
pub const DR_SIM_C: &str = include_str!("../../../runtime/sim/dr_sim.c");

const LIBRARY: &str = "libdrsim.so";

/// Loading and registering the callbacks is serialised: the C side keeps one global table.
static LOAD_LOCK: Mutex<()> = Mutex::new(());
static TEMP_COUNTER: AtomicU64 = AtomicU64::new(0);

pub type InitFn = unsafe extern "C" fn(*mut c_void, *mut c_void);
pub type StepFn = unsafe extern "C" fn(*mut c_void);
pub type ReceiveFn = unsafe extern "C" fn(*mut c_void, u8, *const u8, u8);
pub type QueryFn = unsafe extern "C" fn(*mut c_void) -> u8;
/// `dr_sim_restamp(in, len, robot, execution, out, cap)`: a frame under another robot's
/// identity or of another execution.
pub type RestampFn = unsafe extern "C" fn(*const u8, u8, u16, u32, *mut u8, u8) -> u8;
/// `dr_sim_next_wakeup(m, &at_ms)`: `dr_module_next_wakeup`'s answer bits.
pub type WakeFn = unsafe extern "C" fn(*mut c_void, *mut u32) -> u8;
type SizeFn = unsafe extern "C" fn() -> u32;
type RegisterFn = unsafe extern "C" fn(*const ffi::Callbacks);

/// The protocol-agnostic entry points of a compiled program.
#[derive(Clone, Copy)]
pub struct Entry {
    pub init: InitFn,
    pub step: StepFn,
    pub receive: ReceiveFn,
    pub finished: QueryFn,
    pub address: QueryFn,
    /// `dr_sim_describe`: the protocol state as text (`dr_module_describe`).
    pub describe: DescribeFn,
    pub restamp: RestampFn,
    pub next_wakeup: WakeFn,
    pub module_size: usize,
}

/// A compiled program, loaded. The entry points are valid while `_library` lives.
pub struct Loaded {
    _library: libloading::Library,
    pub entry: Entry,
    pub directory: PathBuf,
    /// True when this build was found in the cache.
    pub cached: bool,
}

/// Where builds are cached: `$DYNAROLE_SIM_CACHE`, else `dynarole-sim` in the temp directory.
pub fn cache_root() -> PathBuf {
    std::env::var_os("DYNAROLE_SIM_CACHE")
        .map(PathBuf::from)
        .unwrap_or_else(|| std::env::temp_dir().join("dynarole-sim"))
}

/// The names in the cache root `root`, sorted: a directory per build (named by its key) and,
/// while builds are under way or after one was killed, their `tmp-` directories. What a test
/// or a tool looks at to see what the cache holds.
pub fn cache_entries(root: &Path) -> std::io::Result<Vec<String>> {
    let mut names = Vec::new();
    for entry in std::fs::read_dir(root)? {
        names.push(entry?.file_name().to_string_lossy().into_owned());
    }
    names.sort();
    Ok(names)
}

/// Builds (or finds in the cache) and loads `files` (name, text) with `defines` (-D flags).
pub fn build_and_load(files: &[(String, String)], defines: &[String]) -> Result<Loaded, String> {
    let key = cache_key(files, defines);
    let directory = cache_root().join(format!("{key:016x}"));
    let library = directory.join(LIBRARY);
    let cached = library.is_file();
    if !cached {
        build(files, defines, &directory)?;
    }
    let (lib, entry) = load(&library)?;
    Ok(Loaded {
        _library: lib,
        entry,
        directory,
        cached,
    })
}

/// FNV-1a (64 bits) over every input of the build: stable across Rust releases.
fn cache_key(files: &[(String, String)], defines: &[String]) -> u64 {
    let mut hash: u64 = 0xcbf2_9ce4_8422_2325;
    let mut feed = |bytes: &[u8]| {
        for b in bytes.iter().chain(&[0u8]) {
            hash ^= u64::from(*b);
            hash = hash.wrapping_mul(0x0100_0000_01b3);
        }
    };
    feed(DR_SIM_C.as_bytes());
    // The flags too: a build made with other warnings or options is not this one.
    for flag in compile_flags() {
        feed(flag.as_bytes());
    }
    for (name, text) in files {
        feed(name.as_bytes());
        feed(text.as_bytes());
    }
    for d in defines {
        feed(d.as_bytes());
    }
    feed(env!("CARGO_PKG_VERSION").as_bytes());
    hash
}

/// Writes the files into a fresh temporary directory, compiles, then renames it into place.
fn build(files: &[(String, String)], defines: &[String], directory: &Path) -> Result<(), String> {
    publish(directory, LIBRARY, |temp| {
        write_and_compile(files, defines, temp)
    })
}

/// Makes `directory` with `make` so that no process ever sees it half made, however many
/// build it at once (shards starting together on one node, or on nodes sharing the cache over
/// a network file system): each makes its own temporary directory, then renames it into
/// place; a loser of the race drops its copy and uses the winner's, once it holds `product`
/// (a path inside it). Every build the cache holds (the simulator's libraries, the firmware
/// images) is published this way.
pub(crate) fn publish(
    directory: &Path,
    product: &str,
    make: impl FnOnce(&Path) -> Result<(), String>,
) -> Result<(), String> {
    let root = directory.parent().unwrap_or(directory);
    std::fs::create_dir_all(root).map_err(|e| format!("cannot create {}: {e}", root.display()))?;
    let temp = fresh_directory(root)?;
    let result = make(&temp);
    if result.is_ok() && std::fs::rename(&temp, directory).is_ok() {
        return Ok(());
    }
    let _ = std::fs::remove_dir_all(&temp);
    result?;
    if directory.join(product).is_file() {
        Ok(())
    } else {
        Err(format!(
            "cannot move the build into {}",
            directory.display()
        ))
    }
}

/// A new, empty directory in `root` of this process alone: creating a directory fails when it
/// exists (also over NFS), so two processes with the same id on two machines get two.
fn fresh_directory(root: &Path) -> Result<PathBuf, String> {
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.subsec_nanos());
    for _ in 0..64 {
        let n = TEMP_COUNTER.fetch_add(1, Ordering::Relaxed);
        let temp = root.join(format!("tmp-{}-{nanos}-{n}", std::process::id()));
        match std::fs::create_dir(&temp) {
            Ok(()) => return Ok(temp),
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => continue,
            Err(e) => return Err(format!("cannot create {}: {e}", temp.display())),
        }
    }
    Err(format!(
        "cannot create a build directory in {}",
        root.display()
    ))
}

/// The runtime's language and warning flags (`runtime/dr_warn.mk`, the one list every C build
/// of dynarole uses: C99, pedantic, `-Wconversion`, `-Wshadow`, every warning an error), then
/// what a loadable library needs.
fn compile_flags() -> Vec<&'static str> {
    let mut flags = dynarole_codegen::warning_flags();
    flags.extend(["-O2", "-shared", "-fPIC", "-I."]);
    flags
}

fn write_and_compile(
    files: &[(String, String)],
    defines: &[String],
    dir: &Path,
) -> Result<(), String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    let mut sources = Vec::new();
    for (name, text) in files
        .iter()
        .map(|(n, t)| (n.as_str(), t.as_str()))
        .chain([("dr_sim.c", DR_SIM_C)])
    {
        std::fs::write(dir.join(name), text)
            .map_err(|e| format!("cannot write {}: {e}", dir.join(name).display()))?;
        if name.ends_with(".c") && name != "dr_meta.c" {
            sources.push(name.to_string());
        }
    }
    let output = Command::new("cc")
        .current_dir(dir)
        .args(compile_flags())
        .args(defines)
        .args(&sources)
        .args(["-o", LIBRARY])
        .output()
        .map_err(|e| format!("cannot run cc: {e}"))?;
    if output.status.success() {
        Ok(())
    } else {
        Err(format!(
            "cc failed on the generated C in {}:\n{}",
            dir.display(),
            String::from_utf8_lossy(&output.stderr)
        ))
    }
}

fn symbol<T: Copy>(lib: &libloading::Library, name: &str) -> Result<T, String> {
    // SAFETY: the symbols are the functions of dr_sim.c with the signatures declared there;
    // the copied pointers are used only while the library is loaded (Loaded keeps it).
    unsafe {
        lib.get::<T>(name.as_bytes())
            .map(|s| *s)
            .map_err(|e| format!("the simulator library has no `{name}`: {e}"))
    }
}

fn load(path: &Path) -> Result<(libloading::Library, Entry), String> {
    let _guard = LOAD_LOCK.lock().unwrap_or_else(|p| p.into_inner());
    // SAFETY: the library is ours (built from dr_sim.c and the generated C); its
    // initialisers do nothing.
    let lib = unsafe { libloading::Library::new(path) }
        .map_err(|e| format!("cannot load {}: {e}", path.display()))?;
    let register: RegisterFn = symbol(&lib, "dr_sim_register")?;
    let size: SizeFn = symbol(&lib, "dr_sim_module_size")?;
    // SAFETY: plain C functions with no preconditions; the table is a 'static.
    let module_size = unsafe {
        register(&ffi::CALLBACKS);
        size()
    };
    let entry = Entry {
        init: symbol(&lib, "dr_sim_init")?,
        step: symbol(&lib, "dr_sim_step")?,
        receive: symbol(&lib, "dr_sim_receive")?,
        finished: symbol(&lib, "dr_sim_finished")?,
        address: symbol(&lib, "dr_sim_address")?,
        describe: symbol(&lib, "dr_sim_describe")?,
        restamp: symbol(&lib, "dr_sim_restamp")?,
        next_wakeup: symbol(&lib, "dr_sim_next_wakeup")?,
        module_size: module_size as usize,
    };
    Ok((lib, entry))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Where the child processes of the race test publish (set only for them).
    const RACE_DIR: &str = "DYNAROLE_SIM_PUBLISH_RACE_DIR";

    /// Run by `several_processes_publish_one_build` in each of its child processes: makes the
    /// directory slowly, file by file, as a compiler would.
    #[test]
    #[ignore = "a child of several_processes_publish_one_build"]
    fn publish_from_a_child_process() {
        let Some(directory) = std::env::var_os(RACE_DIR).map(PathBuf::from) else {
            return;
        };
        let me = std::process::id().to_string();
        let made = publish(&directory, LIBRARY, |temp| {
            for name in ["a.c", "b.c", LIBRARY] {
                std::thread::sleep(std::time::Duration::from_millis(30));
                std::fs::write(temp.join(name), &me).map_err(|e| e.to_string())?;
            }
            Ok(())
        });
        assert_eq!(made, Ok(()));
        let winner = std::fs::read_to_string(directory.join("a.c")).unwrap_or_default();
        for name in ["b.c", LIBRARY] {
            let text = std::fs::read_to_string(directory.join(name)).unwrap_or_default();
            assert_eq!(text, winner, "{name} is from another build than a.c");
        }
    }

    #[test]
    fn several_processes_publish_one_build() {
        let root = std::env::temp_dir().join(format!("dynarole-publish-{}", std::process::id()));
        let directory = root.join("0123456789abcdef");
        let _ = std::fs::remove_dir_all(&root);
        let exe = std::env::current_exe().expect("the test binary");
        let children: Vec<_> = (0..6)
            .map(|_| {
                std::process::Command::new(&exe)
                    .args(["--exact", "build::tests::publish_from_a_child_process"])
                    .args(["--ignored", "--quiet", "--test-threads=1"])
                    .env(RACE_DIR, &directory)
                    .stdout(std::process::Stdio::null())
                    .spawn()
                    .expect("a child process")
            })
            .collect();
        for mut child in children {
            assert!(child.wait().expect("the child ends").success());
        }
        let left = cache_entries(&root).expect("the cache root");
        assert_eq!(
            left,
            ["0123456789abcdef"],
            "temporary directories left behind"
        );
        let _ = std::fs::remove_dir_all(&root);
    }
}

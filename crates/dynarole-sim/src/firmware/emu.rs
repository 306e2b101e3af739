//! The emulated hemisphere board (`runtime/avr/emu/dr_avr_emu.c` over simavr), loaded as a shared
//! library: a safe [`Core`] per module over the shim's tiny C functions.

use std::ffi::{c_char, c_void, CString};
use std::path::Path;
use std::ptr::NonNull;
use std::rc::Rc;

/// One entry of a core's log (`struct drav_event`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct Event {
    /// The core's cycle count when it happened.
    pub cycle: u64,
    pub kind: u8,
    pub a: u8,
    pub b: u8,
    reserved: u8,
    reserved2: u32,
}

/// `DRAV_EV_*` of dr_avr_emu.h.
pub const EV_TX: u8 = 1;
pub const EV_WRITE: u8 = 2;
pub const EV_PINS: u8 = 3;
pub const EV_TEXT: u8 = 5;

type OpenFn = unsafe extern "C" fn(*const c_char, *mut c_char, u32) -> *mut c_void;
type CoreFn = unsafe extern "C" fn(*mut c_void);
type RunFn = unsafe extern "C" fn(*mut c_void, u64) -> i32;
type CountFn = unsafe extern "C" fn(*const c_void) -> u64;
type SetRegFn = unsafe extern "C" fn(*mut c_void, u8, u8);
type TakeFn = unsafe extern "C" fn(*mut c_void, *mut Event, u32) -> u32;
type FlagFn = unsafe extern "C" fn(*const c_void) -> i32;
type RxFn = unsafe extern "C" fn(*mut c_void, u8, *const u8, u32) -> i32;
type StackFn = unsafe extern "C" fn(*const c_void) -> u32;
type SizeFn = unsafe extern "C" fn() -> u32;

/// The loaded shim; its function pointers are valid while `_library` lives.
pub struct Library {
    _library: libloading::Library,
    open: OpenFn,
    close: CoreFn,
    reset: CoreFn,
    run: RunFn,
    cycle: CountFn,
    sleep_cycles: CountFn,
    set_reg: SetRegFn,
    take: TakeFn,
    overflowed: FlagFn,
    rx: RxFn,
    stack: StackFn,
}

fn symbol<T: Copy>(lib: &libloading::Library, name: &str) -> Result<T, String> {
    // SAFETY: the names are the functions of dr_avr_emu.h, declared above with their C
    // signatures; the copied pointers are used only while the library is loaded.
    unsafe {
        lib.get::<T>(name.as_bytes())
            .map(|s| *s)
            .map_err(|e| format!("the emulator library has no `{name}`: {e}"))
    }
}

impl Library {
    pub fn load(path: &Path) -> Result<Rc<Library>, String> {
        // SAFETY: the library is ours (dr_avr_emu.c linked with simavr); loading runs no
        // initialiser of ours, and simavr's only register its core tables.
        let library = unsafe { libloading::Library::new(path) }
            .map_err(|e| format!("cannot load {}: {e}", path.display()))?;
        let size: SizeFn = symbol(&library, "drav_event_size")?;
        // SAFETY: a plain C function without arguments.
        let event_size = unsafe { size() };
        if event_size as usize != std::mem::size_of::<Event>() {
            return Err(format!(
                "{}: its log entries have {event_size} bytes, not {}",
                path.display(),
                std::mem::size_of::<Event>()
            ));
        }
        Ok(Rc::new(Library {
            open: symbol(&library, "drav_open")?,
            close: symbol(&library, "drav_close")?,
            reset: symbol(&library, "drav_reset")?,
            run: symbol(&library, "drav_run")?,
            cycle: symbol(&library, "drav_cycle")?,
            sleep_cycles: symbol(&library, "drav_sleep_cycles")?,
            set_reg: symbol(&library, "drav_set_reg")?,
            take: symbol(&library, "drav_take")?,
            overflowed: symbol(&library, "drav_overflowed")?,
            rx: symbol(&library, "drav_rx")?,
            stack: symbol(&library, "drav_stack_high_water")?,
            _library: library,
        }))
    }
}

/// One emulated board with its ATmega128, running an image.
pub struct Core {
    lib: Rc<Library>,
    ptr: NonNull<c_void>,
}

impl Core {
    /// Loads the ELF image at `elf` into a new core, reset.
    pub fn open(lib: &Rc<Library>, elf: &Path) -> Result<Core, String> {
        let path = CString::new(elf.as_os_str().as_encoded_bytes())
            .map_err(|_| format!("{}: a path with a NUL byte", elf.display()))?;
        let mut err = vec![0u8; 512];
        let cap = u32::try_from(err.len()).unwrap_or(u32::MAX);
        // SAFETY: a NUL-terminated path, and an error buffer of `cap` writable bytes.
        let ptr = unsafe { (lib.open)(path.as_ptr(), err.as_mut_ptr().cast::<c_char>(), cap) };
        match NonNull::new(ptr) {
            Some(ptr) => Ok(Core {
                lib: Rc::clone(lib),
                ptr,
            }),
            None => {
                let end = err.iter().position(|b| *b == 0).unwrap_or(err.len());
                Err(String::from_utf8_lossy(&err[..end]).into_owned())
            }
        }
    }

    /// An MCU reset: RAM and I/O cleared, EEPROM kept, the arbiter's queue emptied.
    pub fn reset(&mut self) {
        // SAFETY: `ptr` is a live core from drav_open (closed only in Drop).
        unsafe { (self.lib.reset)(self.ptr.as_ptr()) }
    }

    /// Runs until cycle `cycle`; false when the core has stopped (crashed).
    pub fn run(&mut self, cycle: u64) -> bool {
        // SAFETY: a live core; the shim's callbacks only touch the core itself.
        unsafe { (self.lib.run)(self.ptr.as_ptr(), cycle) == 0 }
    }

    pub fn cycle(&self) -> u64 {
        // SAFETY: a live core, only read.
        unsafe { (self.lib.cycle)(self.ptr.as_ptr()) }
    }

    pub fn sleep_cycles(&self) -> u64 {
        // SAFETY: a live core, only read.
        unsafe { (self.lib.sleep_cycles)(self.ptr.as_ptr()) }
    }

    pub fn set_reg(&mut self, reg: u8, value: u8) {
        // SAFETY: a live core; the shim wraps `reg` into its register file.
        unsafe { (self.lib.set_reg)(self.ptr.as_ptr(), reg, value) }
    }

    /// Appends the core's log entries since the last call to `out`.
    pub fn take(&mut self, out: &mut Vec<Event>) {
        let mut buffer = [Event::default(); 256];
        loop {
            // SAFETY: a live core and a buffer of 256 entries of the C layout (checked at
            // load time).
            let n = unsafe { (self.lib.take)(self.ptr.as_ptr(), buffer.as_mut_ptr(), 256) };
            let n = (n as usize).min(buffer.len());
            out.extend_from_slice(&buffer[..n]);
            if n < buffer.len() {
                return;
            }
        }
    }

    /// Whether the core's log lost entries (never, when it is read every quantum).
    pub fn overflowed(&self) -> bool {
        // SAFETY: a live core, only read.
        unsafe { (self.lib.overflowed)(self.ptr.as_ptr()) != 0 }
    }

    /// Queues a frame for the firmware; false when the board's arbiter had to drop it.
    pub fn rx(&mut self, channel: u8, bytes: &[u8]) -> bool {
        let len = u32::try_from(bytes.len()).unwrap_or(u32::MAX);
        // SAFETY: a live core and `len` readable bytes; the shim copies them.
        unsafe { (self.lib.rx)(self.ptr.as_ptr(), channel, bytes.as_ptr(), len) == 0 }
    }

    /// The deepest stack use since the last reset, in bytes.
    pub fn stack_high_water(&self) -> u32 {
        // SAFETY: a live core, only read.
        unsafe { (self.lib.stack)(self.ptr.as_ptr()) }
    }
}

impl Drop for Core {
    fn drop(&mut self) {
        // SAFETY: the core came from drav_open and is closed exactly once, here.
        unsafe { (self.lib.close)(self.ptr.as_ptr()) }
    }
}

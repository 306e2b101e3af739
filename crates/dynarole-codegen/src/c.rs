//! The C back-end: program tables (lattice protocol, token baseline) or a Fig. 2 state
//! machine (paper protocol), role predicates, statement metadata for checkers, the runtime,
//! and a Makefile.

use crate::choice::Choice;
use crate::options::{op_macro, CompileOptions};
use crate::paper::{paper_machine, pending_slots};
use crate::predicate;
use crate::protocol::default_failure_policy;
use crate::protocol::{Growth, OnFailure, Protocol};
use crate::runtime;
use crate::token::token_tables;
use dynarole_core::check::Label;
use dynarole_core::lower::{Ir, LimitError};
use dynarole_core::RobotApi;
use std::fmt::Write;

/// A compiled directory: file names and contents, and figures the compiler reports.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Generated {
    pub files: Vec<(String, String)>,
    /// Bytes of one state packet on the wire, framing included.
    pub packet_bytes: usize,
    /// What every packet says of its program (`DR_PROGRAM_FINGERPRINT`).
    pub fingerprint: u32,
}

/// The value of `#define NAME` in the embedded runtime file `file` (runtime/), for the sizes
/// the C states once and the compiler must agree with.
fn runtime_define(file: &str, name: &str) -> Option<usize> {
    runtime_define_text(file, name)
        .and_then(|value| value.trim_end_matches('u').parse::<usize>().ok())
}

/// The text of `#define NAME`'s value in the embedded runtime file `file`.
fn runtime_define_text(file: &str, name: &str) -> Option<&'static str> {
    let text = runtime::COMMON
        .iter()
        .chain(Protocol::ALL.iter().flat_map(|p| p.info().runtime))
        .find(|(path, _)| path.rsplit('/').next() == Some(file))
        .map(|(_, text)| *text)?;
    let prefix = format!("#define {name} ");
    text.lines()
        .find_map(|line| line.strip_prefix(prefix.as_str()))
        .map(str::trim)
}

/// A size the embedded runtime defines. The files are embedded at build time and a test reads
/// every size named here: this cannot fail at run time.
fn runtime_size(file: &str, name: &str) -> usize {
    runtime_define(file, name)
        .unwrap_or_else(|| panic!("runtime/{file} defines {name} as a number"))
}

/// Bytes of every frame besides its payload and tag: `DR_PACKET_HEADER` and `DR_PACKET_CRC` of
/// runtime/dr_packet.h, the one place the frame is laid out.
fn packet_overhead() -> usize {
    runtime_size("dr_packet.h", "DR_PACKET_HEADER") + runtime_size("dr_packet.h", "DR_PACKET_CRC")
}

/// The runtime's default receive buffer (`DR_CONF_MAX_PACKET` of runtime/dr_conf.h), raised in
/// a program's configuration when a frame needs more.
fn default_max_packet() -> usize {
    runtime_size("dr_conf.h", "DR_CONF_MAX_PACKET")
}

/// Bytes of `protocol`'s state payload for `ir`: the fixed part its runtime header defines
/// (`Payload::fixed`) and what grows with the sequence.
fn payload_bytes(protocol: Protocol, ir: &Ir, pending_slots: usize) -> usize {
    let info = protocol.info();
    runtime_size(info.header, info.payload.fixed)
        + match info.payload.grows {
            // The done bits; with synchronous groups (DR_CONF_SYNC) the ready bits too, and
            // the countdown after the payload.
            Growth::WindowBits if ir.has_synchronous() => {
                ir.window / 8 * 2 + runtime_size(info.header, "DR_LATTICE_GO_BYTES")
            }
            Growth::WindowBits => ir.window / 8,
            Growth::PendingSlots => pending_slots,
            Growth::Nothing => 0,
        }
}
/// Bytes of the authentication tag of keyed builds: forging one takes about 2^31 tries, years
/// on an infrared channel of tens of packets a second, for 4 bytes more per packet.
pub const PACKET_TAG_BYTES: usize = 4;
/// Most statements a lattice module runs at once, a batch (`DR_CONF_LATTICE_BATCH`, 1 to 9; 1:
/// one at a time). Decided here only: written into every lattice program's
/// `dr_program_conf.h` and into its Promela model, so the image and the model run the same
/// batches; the runtime's own C tests read it from this line (runtime/lattice/Makefile).
pub(crate) const LATTICE_BATCH: usize = 8;

pub fn generate_c(
    ir: &Ir,
    robot: &RobotApi,
    options: &CompileOptions,
) -> Result<Generated, LimitError> {
    let pending_slots = match options.protocol.info().payload.grows {
        Growth::PendingSlots => pending_slots(ir)?,
        Growth::WindowBits | Growth::Nothing => 0,
    };
    let machine = match options.protocol {
        Protocol::Lattice => lattice_tables(ir, options),
        Protocol::Paper => paper_machine(ir, options)?,
        Protocol::Token => token_tables(ir, options)?,
    };
    let packet_payload = payload_bytes(options.protocol, ir, pending_slots);
    let tag = if options.key.is_some() {
        PACKET_TAG_BYTES
    } else {
        0
    };
    let packet_bytes = packet_payload + packet_overhead() + tag;
    if packet_bytes > usize::from(u8::MAX) {
        return Err(LimitError {
            message: "a packet longer than 255 bytes (the window is too wide)".into(),
            span: ir.statements.first().map(|s| s.span).unwrap_or_default(),
        });
    }
    let mut files = vec![
        (
            "dr_program_conf.h".to_string(),
            program_conf(ir, options, pending_slots, packet_bytes),
        ),
        ("dr_program.h".to_string(), program_header(ir, options)),
        (
            "dr_program.c".to_string(),
            format!(
                "{}{}{machine}",
                program_prelude(ir, options),
                roles(ir, robot)
            ),
        ),
        ("dr_meta.c".to_string(), meta(ir)),
        ("Makefile".to_string(), makefile(options.protocol)),
    ];
    let protocol_files = options.protocol.info().runtime;
    for (name, text) in runtime::COMMON.iter().chain(protocol_files) {
        files.push((name.to_string(), text.to_string()));
    }
    files.sort();
    let fingerprint = fingerprint(&files);
    stamp_identity(&mut files, fingerprint, options);
    Ok(Generated {
        files,
        packet_bytes,
        fingerprint,
    })
}

/// The C directory plus the TinyOS component that runs it (`--target nesc`).
pub fn generate_nesc(
    ir: &Ir,
    robot: &RobotApi,
    options: &CompileOptions,
) -> Result<Generated, LimitError> {
    let mut generated = generate_c(ir, robot, options)?;
    generated.files.extend(crate::nesc::nesc_files(options));
    generated.files.sort();
    Ok(generated)
}

/// FNV-1a (32 bits) of every generated file, the runtime's included: two programs that differ
/// in anything the modules run (a statement, an argument, a dependency, an option, the runtime)
/// get different fingerprints, so their modules ignore each other's packets. The identity and
/// the key are stamped in afterwards and are not part of it (the key must not leak through it;
/// the execution changes from launch to launch, the program does not).
fn fingerprint(files: &[(String, String)]) -> u32 {
    let mut hash: u32 = 0x811c_9dc5;
    for (name, text) in files {
        for byte in name.bytes().chain([0]).chain(text.bytes()).chain([0]) {
            hash ^= u32::from(byte);
            hash = hash.wrapping_mul(0x0100_0193);
        }
    }
    hash
}

/// Writes the fingerprint, the robot identity, the execution and the key (when keyed) into the
/// program's configuration header and source.
fn stamp_identity(files: &mut [(String, String)], fingerprint: u32, options: &CompileOptions) {
    for (name, text) in files.iter_mut() {
        if name == "dr_program_conf.h" {
            let mut identity = format!(
                "/* Packet identity (runtime/dr_packet.h): the program's fingerprint; the robot's\n * identity and this launch's execution (override at flash time with -DDR_ROBOT_ID=N,\n * -DDR_EXECUTION=N). */\n#define DR_PROGRAM_FINGERPRINT 0x{fingerprint:08X}UL\n#ifndef DR_ROBOT_ID\n#define DR_ROBOT_ID {}u\n#endif\n#ifndef DR_EXECUTION\n#define DR_EXECUTION 0x{:08X}UL\n#endif\n",
                options.robot_id, options.execution
            );
            if options.key.is_some() {
                let _ = writeln!(
                    identity,
                    "/* Keyed build: every packet carries an authentication tag. */\n#define DR_CONF_PACKET_TAG {PACKET_TAG_BYTES}"
                );
            }
            *text = text.replace(CONF_END, &format!("{identity}\n{CONF_END}"));
        } else if name == "dr_program.c" {
            if let Some(key) = options.key {
                let bytes: Vec<String> = key.iter().map(|b| format!("0x{b:02X}u")).collect();
                let _ = write!(
                    text,
                    "\n/* The shared packet key (keep this file private). */\nconst uint8_t dr_packet_key[16] = {{ {} }};\n",
                    bytes.join(", ")
                );
            }
        }
    }
}

/// The last line of `dr_program_conf.h` (the identity is stamped in before it).
const CONF_END: &str = "#endif /* DR_PROGRAM_CONF_H */\n";

fn program_conf(
    ir: &Ir,
    options: &CompileOptions,
    pending_slots: usize,
    packet_bytes: usize,
) -> String {
    let mut out = String::from(
        "/* dr_program_conf.h - sizes this compiled sequence needs (generated by dynarole). */\n",
    );
    out.push_str("#ifndef DR_PROGRAM_CONF_H\n#define DR_PROGRAM_CONF_H\n\n");
    let _ = writeln!(
        out,
        "#define DR_CONF_MAX_STATEMENTS {}",
        ir.statements.len().max(1)
    );
    let _ = writeln!(out, "#define DR_CONF_WINDOW {}", ir.window);
    let _ = writeln!(out, "#define DR_CONF_MAX_ARGS {}", ir.max_args.max(1));
    match options.protocol {
        Protocol::Lattice => lattice_conf(ir, options, &mut out),
        Protocol::Paper => {
            let _ = writeln!(out, "#define DR_CONF_MAX_PENDING {pending_slots}");
        }
        Protocol::Token => {}
    }
    if packet_bytes > default_max_packet() {
        let _ = writeln!(out, "#define DR_CONF_MAX_PACKET {packet_bytes}");
    }
    out.push('\n');
    out.push_str(CONF_END);
    out
}

/// The lattice protocol's part of `dr_program_conf.h`.
fn lattice_conf(ir: &Ir, options: &CompileOptions, out: &mut String) {
    // The image carries only the way of surviving resets this program uses (the program's
    // DR_PROGRAM_NO_NV option says the same).
    let nv = if options.without_nv() {
        "NONE"
    } else {
        "RECORD"
    };
    let _ = writeln!(out, "#define DR_CONF_NV DR_CONF_NV_{nv}");
    let _ = writeln!(
        out,
        "#define DR_CONF_LATTICE_DISSEMINATION {} /* {} */",
        options.dissemination.c_macro(),
        options.dissemination.name()
    );
    // The widths of the statement table's indices (dr_lattice.h).
    let (rows, _) = argument_rows(ir);
    let _ = writeln!(
        out,
        "#define DR_CONF_DEP_ENTRIES {}",
        dependency_entries(ir)
    );
    let _ = writeln!(out, "#define DR_CONF_ARG_ROWS {}", rows.len());
    let _ = writeln!(out, "#define DR_CONF_LATTICE_BATCH {LATTICE_BATCH}");
    failure_conf(options, out);
    if ir.has_synchronous() {
        let _ = writeln!(out, "#define DR_CONF_SYNC 1 /* synchronous groups */");
    }
}

/// The failure policy's lines, where it is not the runtime's default (a program compiled
/// without `--on-failure` and `--retries` has the same configuration as before they existed).
fn failure_conf(options: &CompileOptions, out: &mut String) {
    let (policy, retries) = default_failure_policy();
    if options.on_failure != policy {
        let name = options.on_failure.name();
        let c = options.on_failure.c_macro();
        let _ = writeln!(out, "#define DR_CONF_ON_FAILURE {c} /* {name} */");
    }
    if options.on_failure == OnFailure::Retry && options.retries != retries {
        let _ = writeln!(out, "#define DR_CONF_RETRIES {}", options.retries);
    }
}

fn program_header(ir: &Ir, options: &CompileOptions) -> String {
    let mut out = format!(
        "/* dr_program.h - the compiled sequence {} for robot {} (generated by dynarole). */\n",
        options.name, ir.robot
    );
    out.push_str("#ifndef DR_PROGRAM_H\n#define DR_PROGRAM_H\n\n");
    let _ = writeln!(out, "#include \"{}\"\n", options.protocol.info().header);
    out.push_str("/* Operation codes passed to dr_hal_op_start. */\n");
    for (i, (part, op)) in ir.operations.iter().enumerate() {
        let _ = writeln!(out, "#define {} {i}u", op_macro(part, op));
    }
    let program_type = options.protocol.info().program_type;
    let _ = writeln!(out, "\nextern const {program_type} dr_program;");
    out.push_str("\n/* Starts (or, after a reset, restarts) a module running this sequence. */\n");
    out.push_str("void dr_program_init(dr_module_t *m, void *platform);\n");
    out.push_str(
        "/* Number of connected connectors among the first `count` (the `neighbours` query). */\n",
    );
    out.push_str("uint8_t dr_program_neighbours(struct dr_module *m, uint8_t count);\n");
    out.push_str("\n#endif /* DR_PROGRAM_H */\n");
    out
}

fn program_prelude(ir: &Ir, options: &CompileOptions) -> String {
    let mut out = format!(
        "/* dr_program.c - the compiled sequence {} (generated by dynarole; do not edit). */\n",
        options.name
    );
    out.push_str("#include \"dr_program.h\"\n\n");
    out.push_str("/* Statements, as written (after reversal):\n");
    for (i, s) in ir.statements.iter().enumerate() {
        let _ = writeln!(out, " *   {i:>3}  {}", s.text);
    }
    out.push_str(" */\n\n");
    out.push_str("uint8_t dr_program_neighbours(struct dr_module *m, uint8_t count)\n{\n    uint8_t c;\n    uint8_t n = 0;\n");
    out.push_str("    for (c = 0; c < count; c++) {\n        n = (uint8_t)(n + (dr_hal_connected(m, c) ? 1u : 0u));\n    }\n    return n;\n}\n\n");
    out
}

/// `address_of`: which address this module has, by its ID or by the role predicates.
fn roles(ir: &Ir, robot: &RobotApi) -> String {
    let mut out = String::from("/* The module's address: exactly one label must describe it. */\n");
    out.push_str("static uint8_t dr_program_address_of(struct dr_module *m)\n{\n");
    // Labels M0 to M<n-1> only (`M<k>` is address k): the ID is the address, and no two
    // labels describe one module.
    let ids_only = !ir.addresses.is_empty()
        && ir.addresses.iter().enumerate().all(|(k, a)| match a.label {
            Label::Module(id) => usize::try_from(id).is_ok_and(|id| id == k),
            Label::Role(_) => false,
        });
    if ids_only {
        let _ = writeln!(
            out,
            "    /* Labels M0 to M{last} only: the module's ID is its address. */\n    uint16_t id = dr_hal_id(m);\n    return id <= {last}u ? (uint8_t)id : DR_NO_ADDRESS;\n}}\n",
            last = ir.addresses.len() - 1
        );
        return out;
    }
    out.push_str("    uint8_t found = DR_NO_ADDRESS;\n    uint8_t n = 0;\n");
    // The ID is asked once for every `M<k>` label (a call per label costs flash on an MCU).
    let by_id = ir
        .addresses
        .iter()
        .any(|a| matches!(a.label, Label::Module(_)));
    if by_id {
        out.push_str("    uint16_t id = dr_hal_id(m);\n");
    }
    // No label, or only constant predicates, ask the module nothing.
    out.push_str("    (void)m;\n");
    for address in &ir.addresses {
        let test = match (&address.label, &address.predicate) {
            (Label::Module(id), _) => format!("id == {id}u"),
            (Label::Role(_), Some(predicate)) => predicate::to_c(predicate, robot),
            (Label::Role(_), None) => "0".into(),
        };
        let what = match &address.label {
            Label::Module(id) => format!("M{id}"),
            Label::Role(role) => format!("role {role}"),
        };
        let _ = writeln!(
            out,
            "    if ({test}) {{ /* {what} */\n        found = {}u;\n        n++;\n    }}",
            address.number
        );
    }
    out.push_str("    return n > 1u ? DR_MANY_ADDRESSES : found;\n}\n\n");
    out
}

/// Entries of the lattice dependency table: every statement's `waits_for`, one after another.
fn dependency_entries(ir: &Ir) -> usize {
    ir.statements.iter().map(|s| s.waits_for().len()).sum()
}

/// The lattice argument table: each distinct argument list once (padded with zeros to
/// `max_args`, in order of first use; one row of zeros when there are no statements), and
/// each statement's row. Most statements share their arguments (every connector operation
/// has none), so a row number in the statement table costs less flash than the arguments.
fn argument_rows(ir: &Ir) -> (Vec<Vec<i16>>, Vec<usize>) {
    let mut rows: Vec<Vec<i16>> = Vec::new();
    let mut row_of = Vec::with_capacity(ir.statements.len());
    for s in &ir.statements {
        let mut args = s.args.clone();
        args.resize(ir.max_args.max(1), 0);
        let row = match rows.iter().position(|r| *r == args) {
            Some(row) => row,
            None => {
                rows.push(args);
                rows.len() - 1
            }
        };
        row_of.push(row);
    }
    if rows.is_empty() {
        rows.push(vec![0; ir.max_args.max(1)]);
    }
    (rows, row_of)
}

fn lattice_tables(ir: &Ir, options: &CompileOptions) -> String {
    let mut out = String::from("static const dr_dep_t dr_program_deps[] DR_TABLE = {\n");
    let mut first = Vec::new();
    let mut count = 0usize;
    for s in &ir.statements {
        first.push(count);
        let waits = s.waits_for();
        count += waits.len();
        let deps: Vec<String> = waits.iter().map(|d| format!("{d}u")).collect();
        if !deps.is_empty() {
            let _ = writeln!(out, "    {},", deps.join(", "));
        }
    }
    if count == 0 {
        out.push_str("    0u /* no dependencies */\n");
    }
    out.push_str("};\n\n/* Argument lists, each once (DR_CONF_MAX_ARGS per row). */\n");
    out.push_str("static const int16_t dr_program_args[] DR_TABLE = {\n");
    let (rows, row_of) = argument_rows(ir);
    for (row, args) in rows.iter().enumerate() {
        let args: Vec<String> = args.iter().map(|a| a.to_string()).collect();
        let _ = writeln!(out, "    {}, /* {row} */", args.join(", "));
    }
    out.push_str("};\n\nstatic const dr_statement_t dr_program_statements[] DR_TABLE = {\n");
    let sync = ir.has_synchronous();
    for (i, s) in ir.statements.iter().enumerate() {
        let (part, op) = &ir.operations[usize::from(s.op)];
        // A member's group: its size and its place in it (dr_lattice.h, DR_CONF_SYNC only).
        let group = match (sync, s.synchronous) {
            (false, _) => String::new(),
            (true, None) => ", 0u, 0u".to_string(),
            (true, Some(g)) => format!(", {}u, {}u", g.size, i - usize::from(g.first)),
        };
        let _ = writeln!(
            out,
            "    {{ {}u, {}, {}u, {}u, {}u, {}u{group} }}, /* {i}: {} */",
            s.address,
            op_macro(part, op),
            s.index,
            s.waits_for().len(),
            first[i],
            row_of[i],
            s.text
        );
    }
    if ir.statements.is_empty() {
        // C99 has no empty arrays; n_statements stays 0, so the runtime never reads it.
        out.push_str("    { 0u, 0u, 0u, 0u, 0u, 0u } /* no statements */\n");
    }
    out.push_str("};\n\n");
    let _ = writeln!(
        out,
        "const dr_program_t dr_program = {{\n    DR_PROGRAM_FINGERPRINT,\n    {}u, /* statements */\n    dr_program_statements,\n    dr_program_deps,\n    dr_program_args,\n    {}u, /* epochs (0: forever) */\n    dr_program_address_of,\n    {} /* options */\n}};\n",
        ir.statements.len(),
        options.epochs,
        if options.no_nv { "DR_PROGRAM_NO_NV" } else { "0u" }
    );
    out.push_str("void dr_program_init(dr_module_t *m, void *platform)\n{\n    dr_module_init(m, &dr_program, platform);\n}\n");
    out
}

/// Per-statement facts for checkers and harnesses (not needed on the modules).
fn meta(ir: &Ir) -> String {
    let mut out = String::from("/* dr_meta.c - what each statement is, for checkers and test harnesses (generated; not\n * needed on the modules). */\n#include <stdint.h>\n\n");
    let list = |values: Vec<String>| {
        if values.is_empty() {
            "0".to_string()
        } else {
            values.join(", ")
        }
    };
    let _ = writeln!(
        out,
        "const uint16_t dr_meta_n_statements = {}u;",
        ir.statements.len()
    );
    let column = |f: &dyn Fn(&dynarole_core::lower::IrStatement) -> String| {
        list(ir.statements.iter().map(f).collect())
    };
    let _ = writeln!(
        out,
        "const uint8_t dr_meta_address[] = {{ {} }};",
        column(&|s| format!("{}u", s.address))
    );
    let _ = writeln!(
        out,
        "const uint8_t dr_meta_op[] = {{ {} }};",
        column(&|s| format!("{}u", s.op))
    );
    let _ = writeln!(
        out,
        "const uint8_t dr_meta_index[] = {{ {} }};",
        column(&|s| format!("{}u", s.index))
    );
    let _ = writeln!(
        out,
        "const uint8_t dr_meta_n_deps[] = {{ {} }};",
        column(&|s| format!("{}u", s.deps.len()))
    );
    let all_deps: Vec<String> = ir
        .statements
        .iter()
        .flat_map(|s| s.deps.iter().map(|d| format!("{d}u")))
        .collect();
    let _ = writeln!(
        out,
        "const uint16_t dr_meta_deps[] = {{ {} }};",
        list(all_deps)
    );
    out.push_str("const char *const dr_meta_text[] = {\n");
    for s in &ir.statements {
        let _ = writeln!(
            out,
            "    \"{}\",",
            s.text.replace('\\', "\\\\").replace('"', "\\\"")
        );
    }
    out.push_str("    0\n};\n");
    out
}

/// `NAME = words` as a Makefile line, continued with `\` under the first word before a word
/// would pass column 80: the layout the generated Makefile had when it spelled its warning
/// flags itself, so that taking them from `runtime/dr_warn.mk` left its bytes (and every
/// program's fingerprint) unchanged.
fn make_variable(name: &str, words: &[&str]) -> String {
    let indent = " ".repeat(name.len() + 3);
    let mut out = format!("{name} =");
    let mut line = out.len();
    for word in words {
        if line > indent.len() && line + 1 + word.len() > 80 {
            out.push_str(" \\\n");
            out.push_str(&indent);
            out.push_str(word);
            line = indent.len() + word.len();
        } else {
            out.push(' ');
            out.push_str(word);
            line += 1 + word.len();
        }
    }
    out.push('\n');
    out
}

/// The generated Makefile. Host and MCU objects go to their own directories
/// (`build/host/`, `build/$(MCU)/`), so one build never finds the other's objects up to date,
/// and an MCU build without avr-gcc stops with how to install it.
fn makefile(protocol: Protocol) -> String {
    let protocol_source = protocol.info().source;
    let warn = make_variable("WARN", &runtime::warning_flags());
    format!(
        "# Builds the dynarole runtime and this compiled sequence (generated by dynarole).\n\
         #   make                  host build: build/host/libdynarole.a\n\
         #   make MCU=atmega128    avr-gcc build for the ATmega128 microcontroller:\n\
         #                         build/atmega128/libdynarole.a (needs avr-gcc; on Debian or\n\
         #                         Ubuntu: sudo apt-get install gcc-avr avr-libc)\n\
         #   make size             text/data/bss of each object (add MCU=... for the MCU's)\n\
         #   make clean            removes build/\n\
         SRCS = dr_packet.c {protocol_source} dr_program.c\n\
         # The runtime's own warning flags (runtime/*/Makefile): the generated code meets them too.\n\
         {warn}\
         ifeq ($(MCU),)\n\
         BUILD = build/host\n\
         CFLAGS ?= -Os $(WARN)\n\
         SIZE ?= size\n\
         else\n\
         BUILD = build/$(MCU)\n\
         CC = avr-gcc\n\
         AR = avr-ar\n\
         SIZE = avr-size\n\
         # The MCU options, each measured for flash: dr_mcu.mk.\n\
         include dr_mcu.mk\n\
         CFLAGS = $(DR_MCU_FLAGS) -mmcu=$(MCU) $(WARN)\n\
         ifneq ($(filter-out clean,$(or $(MAKECMDGOALS),all)),)\n\
         ifeq ($(shell command -v $(CC)),)\n\
         $(error $(CC) not found, needed for MCU=$(MCU): install it (Debian or Ubuntu: sudo apt-get install gcc-avr avr-libc), or build for the host without MCU)\n\
         endif\n\
         endif\n\
         endif\n\
         OBJS = $(addprefix $(BUILD)/,$(SRCS:.c=.o))\n\n\
         all: $(BUILD)/libdynarole.a\n\n\
         $(BUILD)/libdynarole.a: $(OBJS)\n\
         \t$(AR) rcs $@ $(OBJS)\n\n\
         $(BUILD)/%.o: %.c $(wildcard *.h) | $(BUILD)\n\
         \t$(CC) $(CFLAGS) -c $< -o $@\n\n\
         $(BUILD):\n\
         \tmkdir -p $@\n\n\
         size: $(OBJS)\n\
         \t$(SIZE) $(OBJS)\n\n\
         clean:\n\
         \trm -rf build\n\n\
         .PHONY: all size clean\n"
    )
}

#[cfg(test)]
mod tests {
    use super::{default_max_packet, make_variable, packet_overhead, runtime_define};
    use crate::protocol::Protocol;

    /// Every size the compiler reads from the runtime is there, and the protocol's C builds its
    /// payload from the same constant (so the two cannot drift apart).
    #[test]
    fn the_sizes_come_from_the_runtime_headers() {
        assert_eq!(packet_overhead(), 11);
        assert_eq!(default_max_packet(), 48);
        for protocol in Protocol::ALL {
            let info = protocol.info();
            let fixed = runtime_define(info.header, info.payload.fixed);
            assert!(
                fixed.is_some_and(|n| n > 0),
                "{protocol}: {}",
                info.payload.fixed
            );
            let source = (info.runtime.iter())
                .find(|(name, _)| *name == info.source)
                .map(|(_, text)| *text)
                .unwrap_or_default();
            assert!(
                source.contains(info.payload.fixed),
                "{} does not build its payload from {}",
                info.source,
                info.payload.fixed
            );
        }
    }

    /// The generated Makefile's `WARN` keeps the layout it had when it was written out by hand
    /// (what fits before column 80, then `\` and the rest under the first word), so that its
    /// bytes, and every program's fingerprint, did not change when the flags moved to
    /// `runtime/dr_warn.mk`.
    #[test]
    fn a_make_variable_continues_under_its_first_word_before_column_80() {
        let words = [
            "-std=c99",
            "-one",
            "-two",
            "-three",
            "-four",
            "-five",
            "-six",
            "-seven-eight",
            "-nine-ten-eleven-twelve",
            "-last",
        ];
        assert_eq!(
            make_variable("WARN", &words),
            "WARN = -std=c99 -one -two -three -four -five -six -seven-eight \\\n       \
             -nine-ten-eleven-twelve -last\n"
        );
        assert_eq!(make_variable("V", &["-a"]), "V = -a\n");
        let flags = make_variable("WARN", &crate::runtime::warning_flags());
        assert!(flags.lines().all(|line| line.len() <= 82), "{flags}");
    }
}

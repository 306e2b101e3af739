//! The C back-end end to end: snapshots of the generated state machines for the paper's
//! Fig. 5, a strict-warnings build of the output directory, and the harness running all seven
//! modules of eight2car over a perfect network for both protocols, with operation failures
//! injected for the failure policy.

use dynarole_codegen::{
    generate_c, CompileOptions, Dissemination, Generated, OnFailure, Protocol, TokenRetries,
    TokenRoutes,
};
use dynarole_core::{analyze, parse};
use std::path::{Path, PathBuf};
use std::process::Command;

const FIG5: &str = include_str!("../../../robots/atron/examples/fig5.dr");

fn options(protocol: Protocol) -> CompileOptions {
    CompileOptions {
        protocol,
        name: "eight2car".into(),
        ..CompileOptions::default()
    }
}

fn compile(source: &str, sequence: &str, options: &CompileOptions) -> Generated {
    let parsed = parse(source);
    let (program, diagnostics) = analyze(&parsed.file, &dynarole_robots::plugins());
    let program = program.unwrap_or_else(|| panic!("{diagnostics:?}"));
    let plan = program.expand(sequence).expect("sequence exists");
    let ir = program.lower(&[plan]).expect("fits");
    generate_c(&ir, &program.robot, options).expect("generates")
}

fn file<'g>(generated: &'g Generated, name: &str) -> &'g str {
    generated
        .files
        .iter()
        .find(|(n, _)| n == name)
        .map(|(_, t)| t.as_str())
        .unwrap_or_default()
}

#[test]
fn paper_machine_for_fig5_has_the_states_of_fig2() {
    let generated = compile(FIG5, "eight2car", &options(Protocol::Paper));
    let program = file(&generated, "dr_program.c");
    // Fig. 2: state 1 adds itself as pending and retracts, 2 hands over to state 4 on M3,
    // 3 waits and removes the pending state; 4 and 5 are M3's sequential retract, which falls
    // through to its rotation at 6.
    for expected in [
        "    case 1: /* module 0: M0.Connector[0].retract() & */\n        dr_paper_add_pending(m, 1u);",
        "    case 2:\n        dr_paper_handover(m, 1u, 4u, 3u);",
        "    case 3:\n        if (dr_hal_op_status(m) != DR_OP_DONE) break;\n        dr_paper_remove_pending(m, 1u);",
        "    case 5:\n        if (dr_paper_has_pending(m)) break;\n        if (dr_hal_op_status(m) != DR_OP_DONE) break;\n        m->local_state = 6;\n        /* fall through */\n    case 6:",
        "    case 53: /* module 3: M3.Connector[0].retract() & M3.Connector[2].retract(); */",
    ] {
        assert!(program.contains(expected), "missing:\n{expected}");
    }
    insta::assert_snapshot!(
        "fig5_paper_program_c",
        format!("{FIG5}\n----- dr_program.c (paper) -----\n{program}")
    );
}

#[test]
fn lattice_tables_for_fig5() {
    let generated = compile(FIG5, "eight2car", &options(Protocol::Lattice));
    assert_eq!(
        generated.packet_bytes, 16,
        "11 framing + 4 (epoch, low) + window/8"
    );
    let text = format!(
        "{FIG5}\n----- dr_program_conf.h -----\n{}\n----- dr_program.c (lattice) -----\n{}",
        file(&generated, "dr_program_conf.h"),
        file(&generated, "dr_program.c")
    );
    // The fingerprint hashes the runtime too, so any runtime change moves it; its own tests
    // below say what it must do.
    let fingerprint = format!("0x{:08X}UL", generated.fingerprint);
    let text = text.replace(&fingerprint, "0x<fingerprint>UL");
    insta::assert_snapshot!("fig5_lattice_program_c", text);
}

#[test]
fn roles_become_predicates_over_the_hal() {
    let source = "robot atron;\nrole Driver requires id == 0 && neighbours >= 2;\nrole Wheel requires neighbour_id($CONNECTOR_1) == 1 && !connected($CONNECTOR_0);\nsequence s { Driver.Joint.rotateFromToBy(0, 108, true, 150); Wheel.Connector[$CONNECTOR_2].retract(); M5.Connector[0].extend(); }\n";
    let generated = compile(source, "s", &options(Protocol::Lattice));
    let program = file(&generated, "dr_program.c");
    let roles_start = program
        .find("static uint8_t dr_program_address_of")
        .expect("address_of");
    let roles_end = program[roles_start..]
        .find("\n}\n")
        .map_or(program.len(), |e| roles_start + e + 3);
    insta::assert_snapshot!(
        "roles_address_of",
        format!(
            "{source}\n----- address_of -----\n{}",
            &program[roles_start..roles_end]
        )
    );
}

#[test]
fn module_labels_from_m0_up_make_the_id_the_address() {
    let address_of = |labels: &str| {
        let source = format!("robot atron;\nsequence s {{ {labels} }}\n");
        let generated = compile(&source, "s", &options(Protocol::Lattice));
        let program = file(&generated, "dr_program.c");
        let start = program
            .find("static uint8_t dr_program_address_of")
            .expect("address_of");
        program[start..].to_string()
    };
    // M0, M1, M2: the ID is the address, one comparison.
    let contiguous = address_of(
        "M1.Connector[0].retract(); M0.Connector[0].retract(); M2.Connector[0].extend();",
    );
    assert!(contiguous.contains("return id <= 2u ? (uint8_t)id : DR_NO_ADDRESS;"));
    // M0 and M2 (no M1): module 1 has no address, so every label is tested.
    let gap = address_of("M0.Connector[0].retract(); M2.Connector[0].extend();");
    assert!(gap.contains("if (id == 2u) { /* M2 */"), "{gap}");
    assert!(!gap.contains("id <= "), "{gap}");
}

fn out_dir(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("codegen")
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("output dir");
    dir
}

fn write(generated: &Generated, dir: &Path) {
    for (name, text) in &generated.files {
        std::fs::write(dir.join(name), text).expect("write");
    }
}

fn c_sources(dir: &Path) -> Vec<PathBuf> {
    let mut sources: Vec<PathBuf> = std::fs::read_dir(dir)
        .expect("dir")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "c"))
        .collect();
    sources.sort();
    sources
}

/// The runtime's strict flags (`runtime/dr_warn.mk`: C99, pedantic, every warning an error),
/// the same list the runtime's Makefiles, the generated Makefile and the simulator use.
fn strict() -> Vec<&'static str> {
    dynarole_codegen::warning_flags()
}

/// `cc -std=c99 -c *.c` in the directory, with no include path and every warning an error.
fn builds_alone(dir: &Path) {
    let status = Command::new("cc")
        .args(strict())
        .arg("-c")
        .args(c_sources(dir))
        .current_dir(dir)
        .status()
        .expect("cc runs");
    assert!(
        status.success(),
        "the generated directory does not build on its own"
    );
}

/// Links the directory with the harness and runs seven modules of eight2car.
fn harness_run(dir: &Path) -> String {
    let (stdout, success) = harness_run_with(dir, &[]);
    assert!(success, "{stdout}");
    stdout
}

/// The same with the harness's options `flags` first; what it printed and whether it exited 0.
fn harness_run_with(dir: &Path, flags: &[&str]) -> (String, bool) {
    let harness = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../runtime/harness/harness.c");
    let binary = dir.join("harness");
    let status = Command::new("cc")
        .args(strict())
        .arg("-I")
        .arg(dir)
        .args(c_sources(dir))
        .arg(&harness)
        .arg("-o")
        .arg(&binary)
        .status()
        .expect("cc runs");
    assert!(status.success(), "the harness does not build");
    let out = Command::new(&binary)
        .args(flags)
        .args(["0", "1", "2", "3", "4", "5", "6"])
        .output()
        .expect("harness runs");
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    (stdout, out.status.success())
}

/// Statement 3 of eight2car (M4's first turn) failing in the harness: with the default policy
/// (3 retries) two failures are retried and the sequence ends, each attempt a start of its
/// own; compiled with `stop`, one failure stops M4 and the run says so, without its goal.
#[test]
fn the_harness_fails_operations_and_the_policy_decides_what_follows() {
    let generated = compile(FIG5, "eight2car", &options(Protocol::Lattice));
    let dir = out_dir("lattice-failing");
    write(&generated, &dir);
    let (stdout, success) = harness_run_with(&dir, &["-f", "3:2"]);
    let summary = stdout.lines().last().unwrap_or_default();
    assert!(success && summary.starts_with("finished"), "{summary}");
    assert!(
        summary.contains("25 of 25 statements done, 0 violations"),
        "{summary}"
    );
    assert!(summary.ends_with("2 attempts failed"), "{summary}");
    assert_eq!(stdout.matches(" start  ").count(), 27, "two more starts");
    assert_eq!(stdout.matches(" failed ").count(), 2);
    let stop = CompileOptions {
        on_failure: OnFailure::Stop,
        ..options(Protocol::Lattice)
    };
    let dir = out_dir("lattice-stop");
    write(&compile(FIG5, "eight2car", &stop), &dir);
    let (stdout, success) = harness_run_with(&dir, &["-f", "3:1"]);
    let summary = stdout.lines().last().unwrap_or_default();
    assert!(!success && summary.starts_with("STOPPED"), "{summary}");
    assert!(summary.contains(", 0 violations"), "{summary}");
    assert!(summary.ends_with("1 attempts failed"), "{summary}");
    assert_eq!(stdout.matches(" failed ").count(), 1, "not retried");
}

#[test]
fn both_protocols_run_eight2car_in_dependency_order() {
    let no_nv = CompileOptions {
        no_nv: true,
        ..options(Protocol::Lattice)
    };
    let fixed = CompileOptions {
        dissemination: Dissemination::Fixed,
        ..options(Protocol::Lattice)
    };
    for (name, options) in [
        ("lattice", options(Protocol::Lattice)),
        ("lattice-no-nv", no_nv),
        ("lattice-fixed", fixed),
        ("paper", options(Protocol::Paper)),
    ] {
        let generated = compile(FIG5, "eight2car", &options);
        let dir = out_dir(name);
        write(&generated, &dir);
        builds_alone(&dir);
        let stdout = harness_run(&dir);
        let summary = stdout.lines().last().unwrap_or_default();
        assert!(summary.starts_with("finished"), "{name}: {summary}");
        assert!(
            summary.contains("25 of 25 statements done, 0 violations, 0 re-issued"),
            "{name}: {summary}"
        );
        assert_eq!(
            stdout.matches(" start  ").count(),
            25,
            "{name}: each operation starts once"
        );
    }
}

/// The token baseline's tables, with routes given by hand (the simulator computes real ones
/// from a configuration): a snapshot, and the directory builds on its own.
#[test]
fn token_tables_carry_holders_and_routes() {
    let source = "robot atron;\nsequence s {\n    M0.Connector[0].retract();\n    M3.Connector[4].retract();\n    M3.Joint.rotateFromToBy(0, 108, true, 150);\n    M0.Connector[0].extend();\n}\n";
    let routes = TokenRoutes {
        holders: vec![0, 3, 3, 0],
        routes: vec![vec![], vec![(0, 4), (1, 7)], vec![], vec![(3, 6), (1, 3)]],
    };
    let options = CompileOptions {
        protocol: Protocol::Token,
        token_retries: TokenRetries::Tries(32),
        routes: Some(routes),
        ..options(Protocol::Token)
    };
    let generated = compile(source, "s", &options);
    let program = file(&generated, "dr_program.c");
    assert!(program.contains("{ 0u, 4u }, { 1u, 7u }, /* into 1 */"));
    assert!(program.contains("1u, /* reliable: acknowledged hops (32) */\n    32u"));
    insta::assert_snapshot!(
        "token_program_c",
        format!("{source}\n----- dr_program.c (token) -----\n{program}")
    );
    let dir = out_dir("token");
    write(&generated, &dir);
    builds_alone(&dir);
    // Without routes the token protocol is refused, naming what is missing.
    let parsed = parse(source);
    let (program, _) = analyze(&parsed.file, &dynarole_robots::plugins());
    let program = program.expect("checks");
    let ir = program
        .lower(&[program.expand("s").expect("exists")])
        .expect("fits");
    let error = generate_c(&ir, &program.robot, &options_without_routes()).expect_err("refused");
    assert!(error.message.contains("--from"), "{}", error.message);
}

fn options_without_routes() -> CompileOptions {
    options(Protocol::Token)
}

#[test]
fn nesc_component_wraps_the_same_c() {
    let parsed = parse(FIG5);
    let (program, _) = analyze(&parsed.file, &dynarole_robots::plugins());
    let program = program.expect("checks");
    let ir = program
        .lower(&[program.expand("eight2car").expect("exists")])
        .expect("fits");
    let generated =
        dynarole_codegen::generate_nesc(&ir, &program.robot, &options(Protocol::Lattice))
            .expect("generates");
    let module = file(&generated, "DynaRoleP.nc");
    let configuration = file(&generated, "DynaRoleC.nc");
    insta::assert_snapshot!(
        "nesc_component",
        format!("----- DynaRoleP.nc -----\n{module}----- DynaRoleC.nc -----\n{configuration}")
    );
    // nescc 1.4.0 itself compiles and runs the component in dynarole-cli's tests/nesc.rs;
    // here, with no nesC compiler, the module's body is checked as C, with nesC's event/call
    // syntax spelled as C.
    let body_start =
        module.find("implementation {").expect("implementation") + "implementation {".len();
    let body = &module[body_start..module.rfind('}').expect("closing brace")];
    let as_c = body
        .replace("event void Boot.booted()", "void Boot_booted(void)")
        .replace("event void StepTimer.fired()", "void StepTimer_fired(void)")
        .replace("call StepTimer.startPeriodic", "StepTimer_startPeriodic")
        .replace(" @C() @spontaneous()", "");
    let dir = out_dir("nesc");
    write(&generated, &dir);
    let c_body = format!(
        "#include \"dr_program.h\"\nvoid StepTimer_startPeriodic(uint32_t period);\nvoid Boot_booted(void);\nvoid StepTimer_fired(void);\nvoid dr_platform_receive(uint8_t channel, const uint8_t *bytes, uint8_t len);\n{as_c}"
    );
    std::fs::write(dir.join("nesc_body.c"), c_body).expect("write");
    builds_alone(&dir);
}

#[test]
fn paper_pending_slots_widen_for_wide_parallel_groups() {
    let statements: Vec<String> = (0..7)
        .map(|k| format!("M{k}.Connector[0].retract()"))
        .collect();
    let source = format!(
        "robot atron;\nsequence wide {{ {} & M7.Connector[0].retract(); }}\n",
        statements.join(" & ")
    );
    let generated = compile(&source, "wide", &options(Protocol::Paper));
    assert!(file(&generated, "dr_program_conf.h").contains("#define DR_CONF_MAX_PENDING 7"));
    assert_eq!(generated.packet_bytes, 11 + 3 + 7);
}

#[test]
fn the_fingerprint_tells_programs_apart_that_differ_in_one_speed() {
    // Once a one-byte id, equal for eight2car and eight2car with one turn's speed changed.
    let options = options(Protocol::Lattice);
    let original = compile(FIG5, "eight2car", &options);
    let slower = FIG5.replacen("324, false, 150)", "324, false, 151)", 1);
    assert_ne!(slower, FIG5, "the test must change a speed");
    let changed = compile(&slower, "eight2car", &options);
    assert_ne!(original.fingerprint, changed.fingerprint);
    for generated in [&original, &changed] {
        let conf = file(generated, "dr_program_conf.h");
        let define = format!(
            "#define DR_PROGRAM_FINGERPRINT 0x{:08X}UL",
            generated.fingerprint
        );
        assert!(conf.contains(&define), "{conf}");
    }
    // The same input gives the same fingerprint (it is part of the build's identity).
    assert_eq!(
        compile(FIG5, "eight2car", &options).fingerprint,
        original.fingerprint
    );
}

#[test]
fn robot_identity_and_key_are_stamped_in_and_the_key_adds_its_tag() {
    let plain = compile(FIG5, "eight2car", &options(Protocol::Lattice));
    let keyed_options = CompileOptions {
        robot_id: 513,
        key: Some([0xA5; 16]),
        ..options(Protocol::Lattice)
    };
    let keyed = compile(FIG5, "eight2car", &keyed_options);
    assert_eq!(keyed.packet_bytes, plain.packet_bytes + 4);
    // Identity and key are not part of the fingerprint (the key must not leak through it).
    assert_eq!(keyed.fingerprint, plain.fingerprint);
    let conf = file(&keyed, "dr_program_conf.h");
    assert!(conf.contains("#define DR_ROBOT_ID 513u"), "{conf}");
    assert!(conf.contains("#define DR_CONF_PACKET_TAG 4"), "{conf}");
    assert!(file(&keyed, "dr_program.c").contains("dr_packet_key[16] = { 0xA5u"));
    assert!(!file(&plain, "dr_program.c").contains("dr_packet_key"));
}

#[test]
fn the_execution_is_stamped_in_and_costs_no_byte_on_the_air() {
    let first = CompileOptions {
        key: Some([0x3C; 16]),
        ..options(Protocol::Lattice)
    };
    let second = CompileOptions {
        execution: 0xDEAD_0002,
        ..first.clone()
    };
    let a = compile(FIG5, "eight2car", &first);
    let b = compile(FIG5, "eight2car", &second);
    // One program in two launches: the same fingerprint, the same frame (the execution is
    // folded into the program word, runtime/dr_packet.h), another DR_EXECUTION.
    assert_eq!(a.fingerprint, b.fingerprint);
    assert_eq!(a.packet_bytes, b.packet_bytes);
    let unkeyed = compile(FIG5, "eight2car", &options(Protocol::Lattice));
    assert_eq!(
        b.packet_bytes,
        unkeyed.packet_bytes + 4,
        "the tag's 4 bytes only"
    );
    let conf = file(&b, "dr_program_conf.h");
    assert!(
        conf.contains("#ifndef DR_EXECUTION\n#define DR_EXECUTION 0xDEAD0002UL\n#endif"),
        "{conf}"
    );
    assert!(file(&a, "dr_program_conf.h").contains("#define DR_EXECUTION 0x00000000UL"));
}

/// `make` found on the caller's PATH (the tests below change the PATH make runs with).
fn make_program() -> PathBuf {
    let path = std::env::var_os("PATH").unwrap_or_default();
    std::env::split_paths(&path)
        .map(|d| d.join("make"))
        .find(|p| p.is_file())
        .expect("make on PATH")
}

fn make(dir: &Path, args: &[&str], path: &std::ffi::OsStr) -> std::process::Output {
    Command::new(make_program())
        .args(args)
        .env("PATH", path)
        .current_dir(dir)
        .output()
        .expect("make runs")
}

#[test]
fn host_and_mcu_builds_do_not_share_objects() {
    let dir = out_dir("makefile");
    write(
        &compile(FIG5, "eight2car", &options(Protocol::Lattice)),
        &dir,
    );
    let path = std::env::var_os("PATH").unwrap_or_default();
    let host = make(&dir, &["-s"], &path);
    assert!(host.status.success(), "{host:?}");
    assert!(dir.join("build/host/libdynarole.a").is_file());
    assert!(dir.join("build/host/dr_program.o").is_file());
    assert!(
        !dir.join("dr_program.o").exists(),
        "objects beside the sources"
    );

    // Without avr-gcc: a clear error naming the package, before anything is built.
    let empty = dir.join("no-tools");
    std::fs::create_dir_all(&empty).expect("dir");
    let missing = make(&dir, &["MCU=atmega128"], empty.as_os_str());
    let stderr = String::from_utf8_lossy(&missing.stderr);
    assert!(!missing.status.success());
    assert!(
        stderr.contains("avr-gcc not found") && stderr.contains("apt-get install gcc-avr"),
        "{stderr}"
    );
    assert!(!dir.join("build/atmega128").exists());

    // With avr-gcc (a stand-in: `make -n` only prints the commands), after the host build
    // the MCU build is not "up to date": it compiles every source into its own directory.
    let tools = dir.join("tools");
    std::fs::create_dir_all(&tools).expect("dir");
    for tool in ["avr-gcc", "avr-ar"] {
        let file = tools.join(tool);
        std::fs::write(&file, "#!/bin/sh\nexit 1\n").expect("write");
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&file, std::fs::Permissions::from_mode(0o755)).expect("chmod");
    }
    let with_tools =
        std::env::join_paths(std::iter::once(tools).chain(std::env::split_paths(&path)))
            .expect("PATH");
    let avr = make(&dir, &["-n", "MCU=atmega128"], &with_tools);
    let stdout = String::from_utf8_lossy(&avr.stdout);
    assert!(avr.status.success(), "{avr:?}");
    for source in ["dr_packet", "dr_lattice", "dr_program"] {
        assert!(
            stdout.contains(&format!(
                "avr-gcc -Os -mcall-prologues -mstrict-X -flto -ffat-lto-objects -mrelax -fno-tree-loop-optimize -fno-gcse -fno-move-loop-invariants -mmcu=atmega128 {} -c {source}.c -o build/atmega128/{source}.o",
                strict().join(" ")
            )),
            "{stdout}"
        );
    }
    assert!(
        stdout.contains("avr-ar rcs build/atmega128/libdynarole.a"),
        "{stdout}"
    );
}

/// The symbols `dr_lattice.o` of a compiled directory needs from elsewhere (`cc -Os`, `nm -u`).
fn lattice_imports(dir: &Path) -> String {
    let object = dir.join("dr_lattice.o");
    let status = Command::new("cc")
        .args(strict())
        .args(["-Os", "-c", "dr_lattice.c", "-o"])
        .arg(&object)
        .current_dir(dir)
        .status()
        .expect("cc runs");
    assert!(status.success(), "dr_lattice.c does not build");
    let out = Command::new("nm")
        .arg("-u")
        .arg(&object)
        .output()
        .expect("nm runs");
    assert!(out.status.success());
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// The lattice runtime's way of surviving resets is fixed by the generated header, so an
/// image carries one: with NV it reads and writes the store and never scans its connectors;
/// with `no_nv` the reverse. (With the fixed dissemination: the adaptive one asks which
/// neighbours are connected in both modes, to know who has acknowledged its copy.)
#[test]
fn the_nv_mode_is_chosen_at_compile_time() {
    for no_nv in [false, true] {
        let options = CompileOptions {
            no_nv,
            dissemination: Dissemination::Fixed,
            ..options(Protocol::Lattice)
        };
        let generated = compile(FIG5, "eight2car", &options);
        let mode = if no_nv { "NONE" } else { "RECORD" };
        assert!(file(&generated, "dr_program_conf.h")
            .contains(&format!("#define DR_CONF_NV DR_CONF_NV_{mode}\n")));
        let dir = out_dir(&format!("nv-mode-{mode}"));
        write(&generated, &dir);
        let imports = lattice_imports(&dir);
        for (symbol, wanted) in [
            ("dr_hal_nv_write", !no_nv),
            ("dr_hal_nv_read", !no_nv),
            ("dr_crc16", !no_nv),
            ("dr_hal_connected", no_nv),
        ] {
            assert_eq!(
                imports
                    .lines()
                    .any(|l| l.trim_start().ends_with(&format!(" {symbol}"))),
                wanted,
                "{mode}: {symbol}\n{imports}"
            );
        }
    }
}

/// The dissemination is chosen in the generated configuration, for the lattice protocol only;
/// its names parse back, and anything else is refused with the names there are.
#[test]
fn dissemination_is_configured_for_the_lattice_protocol_only() {
    let conf = |options: &CompileOptions| {
        file(&compile(FIG5, "eight2car", options), "dr_program_conf.h").to_string()
    };
    let adaptive = conf(&options(Protocol::Lattice));
    assert!(adaptive.contains("#define DR_CONF_LATTICE_DISSEMINATION DR_DISSEMINATION_ADAPTIVE"));
    let fixed = conf(&CompileOptions {
        dissemination: Dissemination::Fixed,
        ..options(Protocol::Lattice)
    });
    assert!(fixed.contains("#define DR_CONF_LATTICE_DISSEMINATION DR_DISSEMINATION_FIXED"));
    assert!(!conf(&options(Protocol::Paper)).contains("DISSEMINATION"));
    for mode in Dissemination::ALL {
        assert_eq!(mode.name().parse::<Dissemination>(), Ok(mode));
    }
    assert_eq!(
        "trickle"
            .parse::<Dissemination>()
            .map_err(|e| e.to_string()),
        Err("unknown dissemination `trickle`, expected `adaptive` or `fixed`".to_string())
    );
}

/// The countdown of a synchronous group, read from `runtime/dr_conf.h`: a base and a share
/// per member after the first, both positive.
#[test]
fn the_synchronous_delay_grows_by_one_share_per_member() {
    let one = dynarole_codegen::synchronous_delay_ms(1);
    let share = dynarole_codegen::synchronous_delay_ms(2) - one;
    assert!(one > 0 && share > 0, "{one} {share}");
    assert_eq!(dynarole_codegen::synchronous_delay_ms(20), one + 19 * share);
}

//! The library on its own (spin must be installed: `scripts/test` installs it): a model built
//! from a checked source, checked with the report streamed to an observer, and the
//! counterexample available as data.

use dynarole_codegen::{CompileOptions, Dissemination, PaperMerge, Protocol, TokenRetries};
use dynarole_verify::{
    BuildOptions, Check, Entry, Event, Header, Inputs, Method, Observer, Phase, Source, Verdict,
    VerifyError, VerifyOptions,
};
use std::path::{Path, PathBuf};

fn repo(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(path)
}

const SOURCE: &str = "robots/atron/examples/verify/ab_c.dr";
const LINE: &str = "robots/atron/examples/verify/line3.json";

fn options(protocol: Protocol, merge: PaperMerge) -> BuildOptions {
    BuildOptions {
        compile: CompileOptions {
            protocol,
            merge,
            single_step_handover: false,
            restart_pending: false,
            epochs: 1,
            no_nv: false,
            dissemination: Dissemination::Adaptive,
            token_retries: TokenRetries::Plain,
            routes: None,
            name: "ab_c".into(),
            ..CompileOptions::default()
        },
        method: Method::Auto,
        resets: 0,
        reset_only: Vec::new(),
        late: 0,
        fault: None,
    }
}

/// What an observer is told, in order.
#[derive(Default)]
struct Recorder {
    told: Vec<String>,
    begun: usize,
    ended: usize,
    phases: Vec<Phase>,
}

impl Observer for Recorder {
    fn header(&mut self, header: &Header) {
        self.told.push(header.to_string());
    }
    fn entry(&mut self, entry: &Entry) {
        self.told.push(entry.to_string());
    }
    fn begin(&mut self, _label: &str) {
        self.begun += 1;
    }
    fn progress(&mut self, _label: &str, phase: Phase, _search: Option<(u64, u64)>) {
        if self.phases.last() != Some(&phase) {
            self.phases.push(phase);
        }
    }
    fn end(&mut self) {
        self.ended += 1;
    }
}

/// `ab_c`'s inputs on the line of three modules, and the source's text.
fn with_inputs<T>(then: impl FnOnce(&Inputs, &str) -> T) -> T {
    let text = std::fs::read_to_string(repo(SOURCE)).expect("source");
    let parsed = dynarole_core::parse(&text);
    let registry = dynarole_robots::plugins();
    let (program, diagnostics) = dynarole_core::driver::analyze_all(&parsed, &registry);
    assert!(diagnostics.is_empty(), "{diagnostics:?}");
    let program = program.expect("checked");
    let names = vec!["ab_c".to_string()];
    let plans = dynarole_core::driver::plans(&program, &names).expect("sequence");
    let json = std::fs::read_to_string(repo(LINE)).expect("configuration");
    let config = dynarole_robots::read_configuration(&json).expect("configuration");
    let assignment =
        dynarole_replay::assign_modules(&program, &plans, &config).expect("assignment");
    let world = dynarole_replay::RobotWorld::new(config, &program.robot).expect("world");
    let inputs = Inputs {
        program: &program,
        names: &names,
        plans: &plans,
        assignment: &assignment,
        world: &world,
        configuration: LINE,
    };
    then(&inputs, &text)
}

/// Builds `ab_c` on the line of three modules with `options` and checks it in a fresh
/// directory named `name`.
fn verify(
    options: &BuildOptions,
    name: &str,
) -> (Result<dynarole_verify::Report, VerifyError>, Recorder) {
    with_inputs(|inputs, text| {
        let built = dynarole_verify::build(inputs, options).expect("a model");
        let header = dynarole_verify::header(&built, options, LINE);
        let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
        std::fs::create_dir_all(&dir).expect("a directory");
        let check = VerifyOptions {
            memory_mb: 1024,
            time_s: 300,
            bitstate: false,
            safety_only: false,
        };
        let source = Source { path: SOURCE, text };
        let mut recorder = Recorder::default();
        let report = dynarole_verify::verify(&built, header, &check, source, &dir, &mut recorder);
        (report, recorder)
    })
}
#[test]
fn a_violation_is_streamed_and_its_counterexample_is_data() {
    let (report, recorder) = verify(
        &options(Protocol::Paper, PaperMerge::Java),
        "library-paper-java",
    );
    let report = report.expect("a report");
    assert_eq!(report.verdict, Verdict::Violated);
    // The observer was told the header and every entry, in the report's order.
    let mut whole: Vec<String> = vec![report.header.to_string()];
    whole.extend(report.entries.iter().map(ToString::to_string));
    assert_eq!(recorder.told, whole);
    assert_eq!(recorder.begun, recorder.ended);
    assert!(recorder.begun >= 2, "the search and its shortening");
    assert_eq!(
        recorder.phases[..3],
        [Phase::Generating, Phase::Compiling, Phase::Searching]
    );
    let cx = report.counterexample().expect("a counterexample");
    assert_eq!(cx.check, Check::Safety);
    assert_eq!(cx.module_names, ["M0", "M1", "M2"]);
    // The violation, by module and statement number, is among the events.
    assert!(cx.events.contains(&Event::Violation {
        property: "S1".into(),
        m: 2,
        s: 2
    }));
    assert!(cx.text.starts_with(&cx.explanation.headline));
    assert!(cx
        .explanation
        .headline
        .starts_with("S1 violated: M2 started #2"));
    // Every step tells an event of the trail, in order.
    let events: Vec<usize> = cx.explanation.steps.iter().map(|s| s.event).collect();
    assert!(events.windows(2).all(|w| w[0] < w[1]), "{events:?}");
    assert!(events.iter().all(|&e| e < cx.events.len()));
    assert!(report.to_string().ends_with("result: violated\n"));
}

#[test]
fn the_lattice_protocol_is_verified_with_every_entry_a_verdict() {
    let (report, _) = verify(
        &options(Protocol::Lattice, PaperMerge::CPort),
        "library-lattice",
    );
    let report = report.expect("a report");
    assert_eq!(report.verdict, Verdict::Verified);
    assert!(report.counterexample().is_none());
    let checks: Vec<Check> = report
        .entries
        .iter()
        .filter_map(|e| match e {
            Entry::Checked { name, verdict, .. } => {
                assert_eq!(*verdict, Verdict::Verified);
                Some(name.check)
            }
            _ => None,
        })
        .collect();
    assert_eq!(checks, [Check::Safety, Check::Liveness]);
}

#[test]
fn what_is_not_modelled_is_bad_usage() {
    assert!(matches!(
        dynarole_verify::modelled(Protocol::Token),
        Err(VerifyError::Usage(_))
    ));
    let mut broken = options(Protocol::Paper, PaperMerge::Java);
    broken.method = Method::Compositional;
    with_inputs(|inputs, _| {
        match dynarole_verify::build(inputs, &broken) {
            Err(VerifyError::Usage(m)) => assert!(m.contains("use --method full"), "{m}"),
            Err(other) => panic!("not bad usage: {other:?}"),
            Ok(_) => panic!("the paper protocol modelled compositionally"),
        }
        broken.method = Method::Full;
        broken.reset_only = vec!["M9".into()];
        match dynarole_verify::build(inputs, &broken) {
            Err(VerifyError::Usage(m)) => assert!(m.contains("no module of that name"), "{m}"),
            Err(other) => panic!("not bad usage: {other:?}"),
            Ok(_) => panic!("an unknown module may reset"),
        }
    });
}

/// The fairness bound comes from the processes the generator starts: one per module, per
/// link, per module with statements (its actuator), and the radio of the liveness check.
#[test]
fn the_full_model_knows_its_processes() {
    with_inputs(|inputs, _| {
        let built = dynarole_verify::build(inputs, &options(Protocol::Lattice, PaperMerge::CPort))
            .expect("a model");
        let dynarole_verify::Models::Full(model) = &built.models else {
            panic!("three modules get the full model");
        };
        let mut acting: Vec<u8> = built.ir.statements.iter().map(|s| s.address).collect();
        acting.sort_unstable();
        acting.dedup();
        let t = &built.topology;
        assert_eq!(
            model.processes,
            t.modules.len() + t.links.len() + acting.len() + 1
        );
    });
}

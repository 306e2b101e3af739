//! The token baseline in the simulator: its routes on the eight, eight2car on a perfect
//! network for each variant, and what a cut route does to the plain and the safe token.

mod common;

use common::*;
use dynarole_codegen::{CompileOptions, Protocol, TokenRetries, TokenRoutes};
use dynarole_core::{driver, parse};
use dynarole_replay::token_routes;
use dynarole_sim::{Block, Report, Scenario, Simulator};

fn eight2car_routes() -> TokenRoutes {
    let parsed = parse(EIGHT2CAR);
    let program = driver::check(&parsed, &dynarole_robots::plugins()).expect("eight2car checks");
    let plan = program.expand("eight2car").expect("sequence exists");
    token_routes(&program, &[plan], &config(EIGHT)).expect("every hand-over has a route")
}

fn token_run(retries: TokenRetries, scenario: &Scenario, seed: u64) -> Report {
    let parsed = parse(EIGHT2CAR);
    let program = driver::check(&parsed, &dynarole_robots::plugins()).expect("eight2car checks");
    let plans = vec![program.expand("eight2car").expect("sequence exists")];
    let routes = token_routes(&program, &plans, &config(EIGHT)).expect("routes");
    let options = CompileOptions {
        protocol: Protocol::Token,
        token_retries: retries,
        routes: Some(routes),
        name: "token".into(),
        ..CompileOptions::default()
    };
    let sim = Simulator::new(&program, &plans, &options).expect("compiles");
    run(&sim, EIGHT, Some(CAR), scenario, seed)
}

#[test]
fn routes_follow_the_sequence_on_the_eight() {
    let routes = eight2car_routes();
    assert_eq!(routes.holders.len(), 25);
    // Fig. 5 starts with M0 then M3; the first statement needs no hand-over.
    assert_eq!(&routes.holders[..2], &[0, 3]);
    assert!(routes.routes[0].is_empty());
    for k in 1..25 {
        let route = &routes.routes[k];
        if routes.holders[k] == routes.holders[k - 1] {
            assert!(route.is_empty(), "statement {k} runs on the same module");
        } else {
            // The route leaves from the module that ran the previous statement and never
            // passes a module twice.
            assert_eq!(route.first().map(|h| h.0), Some(routes.holders[k - 1]));
            let mut modules: Vec<u16> = route.iter().map(|h| h.0).collect();
            modules.sort_unstable();
            modules.dedup();
            assert_eq!(modules.len(), route.len(), "statement {k}: {route:?}");
        }
    }
    assert!(
        routes.routes.iter().any(|r| r.len() >= 3),
        "the eight has multi-hop hand-overs: {:?}",
        routes.routes
    );
}

#[test]
fn plain_and_32_tries_complete_eight2car_on_a_perfect_network() {
    for retry in [TokenRetries::Plain, TokenRetries::Tries(32)] {
        let report = token_run(retry, &Scenario::default(), 1);
        assert!(report.success, "{retry:?}: {}", report.summary());
        assert_eq!(report.protocol, "token");
        assert_eq!(report.statements_done, 25);
        assert_eq!(report.configuration_matches, Some(true));
        assert_eq!(report.counters.ops_started, 25);
        // Strictly sequential: slower than the shared-state protocols' ~31 s.
        let completion = report.completion_ms.unwrap_or(0.0);
        assert!(completion > 35_000.0, "{retry:?}: {completion}");
    }
    // The plain token sends one packet per hop and hand-over, plus the end.
    let plain = token_run(TokenRetries::Plain, &Scenario::default(), 1);
    assert!(plain.counters.packets_sent < 100, "{}", plain.summary());
}

/// The original safe token's flaw, reproduced (runtime/token/README.md): a module that has a
/// message of its own waiting does not acknowledge, so two neighbours that hand the token
/// back and forth across a turn (which breaks the links, losing the first acknowledgement)
/// each wait for the other; the messages are retried until their tries run out. With 128 or
/// unlimited tries they outlive the shape: a retried copy reaches a module that is a new
/// neighbour on that connector, which has never seen it, and the token of an old statement
/// comes back (S2) even with no packet lost.
#[test]
fn long_retries_resurrect_old_tokens_after_the_shape_changes() {
    for retry in [TokenRetries::Tries(128), TokenRetries::Unlimited] {
        let report = token_run(retry, &Scenario::default(), 1);
        assert!(!report.success, "{retry:?}: {}", report.summary());
        assert_eq!(report.counters.lost, 0);
        assert!(report.count("S2") > 0, "{retry:?}: {}", report.summary());
    }
}

/// The first hand-over (M0 to M3) leaves M0 on its first route hop; that connector is cut
/// from the start for `cut_ms`.
fn first_route_cut(cut_ms: u64) -> Scenario {
    let routes = eight2car_routes();
    let (module, connector) = routes.routes[1][0];
    let mut scenario = Scenario {
        timeout_ms: 120_000,
        ..Scenario::default()
    };
    scenario.block.push(Block {
        module: format!("M{module}"),
        connector,
        from_ms: 0,
        to_ms: cut_ms,
    });
    scenario
}

#[test]
fn a_cut_route_stalls_the_plain_token_and_delays_the_safe_one() {
    let long_cut = first_route_cut(20_000);
    let plain = token_run(TokenRetries::Plain, &long_cut, 1);
    assert_eq!(plain.completion_ms, None, "{}", plain.summary());
    assert_eq!(plain.counters.ops_started, 1, "{}", plain.summary());
    // 32 tries at 100 ms give up after about 3.2 s: stalled as well.
    let bounded = token_run(TokenRetries::Tries(32), &long_cut, 1);
    assert_eq!(bounded.completion_ms, None, "{}", bounded.summary());
    assert_eq!(bounded.counters.ops_started, 1, "{}", bounded.summary());
    // A cut that ends 2 s after the hand-over, within the tries: done, about 2 s late.
    let free = token_run(TokenRetries::Tries(32), &Scenario::default(), 1);
    let short_cut = first_route_cut(first_start_ms(&free, 1) + 2_000);
    let delayed = token_run(TokenRetries::Tries(32), &short_cut, 1);
    assert!(delayed.success, "{}", delayed.summary());
    let late = delayed.completion_ms.unwrap_or(0.0) - free.completion_ms.unwrap_or(0.0);
    assert!(late > 1_000.0, "{late}");
}

/// When statement `k` first started (ms), from the trace.
fn first_start_ms(report: &Report, k: usize) -> u64 {
    let needle = format!("#{k} ");
    report
        .trace
        .as_deref()
        .unwrap_or_default()
        .lines()
        .find(|l| l.get(20..30).is_some_and(|e| e.trim() == "start") && l.contains(&needle))
        .and_then(|l| l.get(0..12)?.trim().parse::<f64>().ok())
        .map_or(0, |ms| ms as u64)
}

#[test]
fn the_token_baseline_names_the_statement_it_holds() {
    // Every operation the simulator attributes to a module is the statement whose token the
    // module's runtime holds (`tok<N>` in its state), also across a reset.
    let mut scenario = Scenario::default();
    scenario.reset.push(dynarole_sim::Reset {
        module: "M3".into(),
        at_ms: 5_000,
    });
    let report = token_run(TokenRetries::Tries(32), &scenario, 3);
    let trace = report.trace.as_deref().unwrap_or_default();
    let mut starts = 0;
    for line in trace.lines() {
        let event = line.get(20..30).map(str::trim);
        if !matches!(event, Some("start" | "resume" | "retry" | "reissue")) {
            continue;
        }
        let state = line.get(31..59).unwrap_or("");
        let number = line
            .get(60..)
            .and_then(|d| d.strip_prefix('#'))
            .and_then(|d| d.split(' ').next());
        let expected = format!("tok{}", number.unwrap_or("?"));
        assert!(state.split_whitespace().any(|f| f == expected), "{line}");
        starts += 1;
    }
    assert!(starts >= 25, "{}", report.summary());
}

//! The paper protocol's state machine in the shape of Fig. 2, numbered as the original
//! compiler numbered it (protocol notes, e.9).

use crate::options::CompileOptions;
use dynarole_core::lower::{
    Ir, LimitError, PaperUnit, PaperUnitKind, PAPER_ADDRESS_ALL, PAPER_STATE_END,
};
use std::fmt::Write;

/// Pending slots of the paper protocol's packets: the original's 5, widened when a parallel
/// group has more parallel statements than that (as the original's rotation experiments did).
const PAPER_MIN_PENDING_SLOTS: usize = 5;
pub fn paper_machine(ir: &Ir, options: &CompileOptions) -> Result<String, LimitError> {
    let units = ir.paper_layout()?;
    let mut out = args_tables(ir);
    out.push_str(
        "/* One step of the distributed state machine (the shape of the paper's Fig. 2). */\n",
    );
    out.push_str(
        "static void dr_program_step(struct dr_module *m)\n{\n    switch (m->local_state) {\n",
    );
    out.push_str(
        "    case 0: /* entry */\n        m->local_state = 1;\n        /* fall through */\n",
    );
    for (k, unit) in units.iter().enumerate() {
        unit_cases(&mut out, ir, unit, units.get(k + 1));
    }
    out.push_str("    default:\n        break;\n    }\n}\n\n");
    responsibility(&mut out, &units);
    let first_address = ir.statements.first().map_or(0, |s| s.address);
    let merge = options.merge.c_macro();
    let _ = writeln!(
        out,
        "const dr_paper_program_t dr_program = {{\n    DR_PROGRAM_FINGERPRINT,\n    {first_address}u, /* module of the first statement */\n    dr_program_address_of,\n    dr_program_step,\n    dr_program_responsible\n}};\n"
    );
    let _ = writeln!(
        out,
        "void dr_program_init(dr_module_t *m, void *platform)\n{{\n    dr_module_init(m, &dr_program, platform);\n    m->merge = {merge};\n    m->single_step_handover = {}u;\n    m->restart_pending = {}u;\n}}",
        u8::from(options.single_step_handover),
        u8::from(options.restart_pending)
    );
    Ok(out)
}

fn args_tables(ir: &Ir) -> String {
    let mut out = String::new();
    for (i, s) in ir.statements.iter().enumerate() {
        let mut args: Vec<String> = s.args.iter().map(|a| a.to_string()).collect();
        args.resize(ir.max_args.max(1), "0".into());
        let _ = writeln!(
            out,
            "static const int16_t dr_args_{i}[DR_CONF_MAX_ARGS] DR_TABLE = {{ {} }};",
            args.join(", ")
        );
    }
    out.push('\n');
    out
}

fn start(ir: &Ir, i: usize) -> String {
    let s = &ir.statements[i];
    let (part, op) = &ir.operations[usize::from(s.op)];
    format!(
        "        dr_paper_op_start(m, {i}u, DR_OP_{}_{}, {}u, dr_args_{i});\n",
        part.to_uppercase(),
        op.to_uppercase(),
        s.index
    )
}

/// After the last wait: fall through to the next statement on this module, hand the state to
/// the next module, or announce the end.
fn transfer(out: &mut String, unit: &PaperUnit, next: Option<&PaperUnit>) {
    let last_state = u32::from(unit.first_state) + 1;
    match next {
        Some(n) if n.address == unit.address => {
            let _ = writeln!(
                out,
                "        m->local_state = {};\n        /* fall through */",
                last_state + 1
            );
        }
        Some(n) => {
            let _ = writeln!(out, "        dr_paper_send_state(m, {}u, {}u);\n        m->local_state = DR_STATE_IDLE;\n        break;", n.first_state, n.address);
        }
        None => {
            out.push_str("        dr_paper_send_state(m, DR_STATE_END, DR_ADDRESS_ALL);\n        m->local_state = DR_STATE_IDLE;\n        break;\n");
        }
    }
}

fn unit_cases(out: &mut String, ir: &Ir, unit: &PaperUnit, next: Option<&PaperUnit>) {
    let s = unit.first_state;
    let texts: Vec<&str> = unit
        .statements
        .iter()
        .map(|&i| ir.statements[i].text.as_str())
        .collect();
    match unit.kind {
        PaperUnitKind::Parallel => {
            let i = unit.statements[0];
            let (next_state, next_address) = next
                .map_or((PAPER_STATE_END, PAPER_ADDRESS_ALL), |n| {
                    (n.first_state, n.address)
                });
            let _ = writeln!(
                out,
                "    case {s}: /* module {}: {} & */",
                unit.address,
                texts.join(" & ")
            );
            let _ = writeln!(out, "        dr_paper_add_pending(m, {s}u);");
            out.push_str(&start(ir, i));
            let _ = writeln!(
                out,
                "        m->local_state = {};\n        break;",
                u32::from(s) + 1
            );
            // sendState of Fig. 2; with the single-step option the runtime re-adds S in the
            // same step, so the transfer always carries it.
            let _ = writeln!(
                out,
                "    case {}:\n        dr_paper_handover(m, {s}u, {next_state}u, {next_address}u);",
                u32::from(s) + 1
            );
            let _ = writeln!(
                out,
                "        m->local_state = {};\n        /* fall through */",
                u32::from(s) + 2
            );
            let _ = writeln!(
                out,
                "    case {}:\n        if (dr_hal_op_status(m) != DR_OP_DONE) break;",
                u32::from(s) + 2
            );
            let _ = writeln!(out, "        dr_paper_remove_pending(m, {s}u);\n        m->local_state = DR_STATE_IDLE;\n        break;");
        }
        PaperUnitKind::Sequential | PaperUnitKind::Block => {
            let joined = texts.join(" & ");
            let _ = writeln!(
                out,
                "    case {s}: /* module {}: {joined}; */",
                unit.address
            );
            for &i in &unit.statements {
                out.push_str(&start(ir, i));
            }
            let _ = writeln!(
                out,
                "        m->local_state = {};\n        break;",
                u32::from(s) + 1
            );
            let _ = writeln!(out, "    case {}:", u32::from(s) + 1);
            if unit.kind == PaperUnitKind::Sequential {
                // A block does not look at the pending set (a quirk of the original compiler).
                out.push_str("        if (dr_paper_has_pending(m)) break;\n");
            }
            out.push_str("        if (dr_hal_op_status(m) != DR_OP_DONE) break;\n");
            transfer(out, unit, next);
        }
    }
}

/// `checkPendingStateResponsibility`: whether `address` runs the parallel statement that
/// starts at `state`.
fn responsibility(out: &mut String, units: &[PaperUnit]) {
    out.push_str("static uint8_t dr_program_responsible(uint8_t address, uint8_t state)\n{\n    (void)address; /* unused when the sequence has no parallel statement */\n    switch (state) {\n");
    for unit in units.iter().filter(|u| u.kind == PaperUnitKind::Parallel) {
        let _ = writeln!(
            out,
            "    case {}: return (uint8_t)(address == {}u);",
            unit.first_state, unit.address
        );
    }
    out.push_str("    default: return 0;\n    }\n}\n\n");
}

/// The most parallel statements that can be pending at once: those of one parallel group.
pub(crate) fn pending_slots(ir: &Ir) -> Result<usize, LimitError> {
    let mut most = 0usize;
    let mut run = 0usize;
    for unit in ir.paper_layout()? {
        if unit.kind == dynarole_core::lower::PaperUnitKind::Parallel {
            run += 1;
            most = most.max(run);
        } else {
            run = 0;
        }
    }
    Ok(most.max(PAPER_MIN_PENDING_SLOTS))
}

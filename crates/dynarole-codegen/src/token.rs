//! The token baseline's tables: every statement with the module that runs it and the route
//! its token takes to get there (computed by the caller on a configuration), for
//! `runtime/token/dr_token.c`.

use crate::options::{op_macro, CompileOptions};
use crate::protocol::TokenRetries;
use dynarole_core::lower::{Ir, LimitError};
use std::fmt::Write;

pub use dynarole_core::lower::TokenRoutes;

/// `dr_program.c`'s tables and program for the token runtime.
pub fn token_tables(ir: &Ir, options: &CompileOptions) -> Result<String, LimitError> {
    let first_span = ir.statements.first().map(|s| s.span).unwrap_or_default();
    let limit = |message: &str| LimitError {
        message: message.into(),
        span: first_span,
    };
    let routes = options.routes.as_ref().ok_or_else(|| {
        limit("the token protocol routes its hand-overs on a configuration: give one with --from")
    })?;
    if routes.holders.len() != ir.statements.len() || routes.routes.len() != ir.statements.len() {
        return Err(limit(
            "the token routes were computed for another sequence (statement counts differ)",
        ));
    }
    let mut out = String::from(
        "/* Hand-over routes: each hop is (module ID, connector it sends the token on). */\n",
    );
    out.push_str("static const dr_token_hop_t dr_program_hops[] DR_TABLE = {\n");
    let mut first_hop = Vec::with_capacity(ir.statements.len());
    let mut count = 0usize;
    for (i, route) in routes.routes.iter().enumerate() {
        first_hop.push(count);
        count += route.len();
        if !route.is_empty() {
            let hops: Vec<String> = route
                .iter()
                .map(|(m, c)| format!("{{ {m}u, {c}u }}"))
                .collect();
            let _ = writeln!(out, "    {}, /* into {i} */", hops.join(", "));
        }
    }
    if count == 0 {
        out.push_str("    { 0u, 0u } /* no hand-over leaves a module */\n");
    }
    out.push_str("};\n\nstatic const dr_token_statement_t dr_program_statements[] DR_TABLE = {\n");
    for (i, s) in ir.statements.iter().enumerate() {
        let (part, op) = &ir.operations[usize::from(s.op)];
        let mut args: Vec<String> = s.args.iter().map(|a| a.to_string()).collect();
        args.resize(ir.max_args.max(1), "0".into());
        let hops = u8::try_from(routes.routes[i].len())
            .map_err(|_| limit("a hand-over route longer than 255 hops"))?;
        let _ = writeln!(
            out,
            "    {{ {}u, {}, {}u, {}u, {}u, {hops}u, {{ {} }} }}, /* {i}: {} */",
            s.address,
            op_macro(part, op),
            s.index,
            routes.holders[i],
            first_hop[i],
            args.join(", "),
            s.text
        );
    }
    if ir.statements.is_empty() {
        // C99 has no empty arrays; the program's count stays 0, so the runtime never reads it.
        out.push_str("    { 0u, 0u, 0u, 0u, 0u, 0u, { 0 } } /* no statements */\n");
    }
    let (reliable, tries) = match options.token_retries {
        TokenRetries::Plain => (0, 1),
        TokenRetries::Tries(n) => (1, n.max(1)),
        TokenRetries::Unlimited => (1, 0),
    };
    out.push_str("};\n\n");
    let _ = writeln!(
        out,
        "const dr_token_program_t dr_program = {{\n    DR_PROGRAM_FINGERPRINT,\n    {}u, /* statements */\n    dr_program_statements,\n    dr_program_hops,\n    dr_program_address_of,\n    {reliable}u, /* reliable: acknowledged hops ({}) */\n    {tries}u /* tries per message (0: unlimited) */\n}};\n",
        ir.statements.len(),
        options.token_retries.name(),
    );
    out.push_str("void dr_program_init(dr_module_t *m, void *platform)\n{\n    dr_module_init(m, &dr_program, platform);\n}\n");
    Ok(out)
}

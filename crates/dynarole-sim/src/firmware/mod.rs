//! `dynarole simulate --firmware avr`: every module runs the ATmega128 image that
//! `dynarole compile --target c` and `runtime/avr` make, on an emulated hemisphere board (runtime/avr, simavr);
//! the simulator's network, world, faults, checks and traces stay as they are (docs/simulator.md).

mod emu;
mod image;
mod runner;

pub use runner::{FirmwareReport, ModuleFirmware};

use crate::state::State;
use crate::{Outputs, Report, Run, SimError, Simulator};
use std::sync::Arc;

/// `DR_CONF_MAX_ARGS` of the generated program (dr_program_conf.h), else dr_conf.h's default.
fn max_args(files: &[(String, String)]) -> usize {
    files
        .iter()
        .filter(|(name, _)| name == "dr_program_conf.h")
        .flat_map(|(_, text)| text.lines())
        .find_map(|line| {
            line.strip_prefix("#define DR_CONF_MAX_ARGS ")
                .and_then(|v| v.trim().parse().ok())
        })
        .unwrap_or(4)
}

/// What the firmware image is made from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FirmwareSource {
    /// The generated C (`--target c`) with runtime/avr's platform and main.
    C,
    /// The generated nesC component (`--target nesc`) compiled by nesC 1.4.0 against
    /// runtime/nesc, with runtime/avr's platform driving it.
    Nesc,
}

impl Simulator {
    /// Like [`Simulator::run`], with every module an emulated ATmega128 running the firmware
    /// image made from `source`; also returns the image's footprint and each module's
    /// measurements. Scenarios with packets of another robot (`foreign`) are refused: the
    /// firmware only sends its own.
    pub fn run_firmware(
        &self,
        run: &Run,
        source: FirmwareSource,
    ) -> Result<(Report, FirmwareReport), SimError> {
        self.run_firmware_with(run, source, Outputs::default())
    }

    /// [`Simulator::run_firmware`] writing `outputs` as it goes ([`Simulator::run_with`]).
    pub fn run_firmware_with(
        &self,
        run: &Run,
        source: FirmwareSource,
        outputs: Outputs,
    ) -> Result<(Report, FirmwareReport), SimError> {
        if !run.scenario.foreign.is_empty() {
            return Err(SimError::Input(
                "scenario: packets of another robot (`foreign`) are not supported with --firmware avr".into(),
            ));
        }
        image::check_tools(source).map_err(SimError::Build)?;
        let world = self.world_for(run)?;
        let preset = crate::preset_of(&world, run.scenario).map_err(SimError::Input)?;
        let durations = self.run_durations(run.scenario)?;
        let mut defines = vec![format!(
            "-DDR_CONF_BROADCAST_JITTER_MS={}",
            preset.jitter_ms
        )];
        if run.trace || outputs.trace.is_some() || outputs.record {
            // The trace's state column: the firmware describes its state in RAM.
            defines.push("-DDR_AVR_DESCRIBE".into());
        }
        let image = match source {
            FirmwareSource::C => image::image(&self.files, &defines),
            FirmwareSource::Nesc => image::nesc_image(&self.files, &self.nesc, &defines),
        }
        .map_err(SimError::Build)?;
        let lib = emu::Library::load(&image::emulator().map_err(SimError::Build)?)
            .map_err(SimError::Build)?;
        let mut state = State::new(
            Arc::clone(&self.sequence),
            (world, preset, durations),
            run.scenario.clone(),
            run.seed,
            run.trace,
        );
        state.set_outputs(outputs);
        let (mut finished, firmware) =
            runner::run(&lib, &image, max_args(&self.files), state).map_err(SimError::Build)?;
        finished.state.flush_trace().map_err(SimError::Trace)?;
        Ok((self.report(run, finished), firmware))
    }
}

#[cfg(test)]
mod tests {
    use super::max_args;

    #[test]
    fn max_args_comes_from_the_generated_configuration() {
        let conf = |text: &str| vec![("dr_program_conf.h".to_string(), text.to_string())];
        assert_eq!(
            max_args(&conf(
                "#define DR_CONF_WINDOW 8\n#define DR_CONF_MAX_ARGS 6\n"
            )),
            6
        );
        assert_eq!(max_args(&conf("#define DR_CONF_WINDOW 8\n")), 4);
        assert_eq!(max_args(&[]), 4);
    }
}

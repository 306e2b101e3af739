/* DrMainP.nc - the C entry points a platform calls (dr_nesc_platform.h). */
module DrMainP {
    provides interface Boot;
    uses interface Scheduler;
    uses interface Clock;
}
implementation {
    /* Whether tasks were left waiting by the last runTasks (it stopped at its bound). */
    bool waiting;

    /* Runs waiting tasks, at most DR_NESC_MAX_TASK_RUNS (see dr_nesc_platform.h). */
    void runTasks() {
        uint8_t runs;
        waiting = TRUE;
        for (runs = 0; runs < DR_NESC_MAX_TASK_RUNS; runs++) {
            if (!call Scheduler.runNextTask()) {
                waiting = FALSE;
                break;
            }
        }
    }

    void dr_nesc_boot() @C() @spontaneous() {
        call Scheduler.init();
        signal Boot.booted();
        runTasks();
    }

    void dr_nesc_advance_ms(uint32_t ms) @C() @spontaneous() {
        call Clock.advance(ms);
        runTasks();
    }

    uint32_t dr_nesc_until_due_ms() @C() @spontaneous() {
        uint32_t ms = 0;
        if (!waiting) {
            call Clock.untilDue(&ms);
        }
        return ms;
    }
}

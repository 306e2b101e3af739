/* DrMainP.nc - the C entry points a platform calls (dr_nesc_platform.h). */
module DrMainP {
    provides interface Boot;
    uses interface Scheduler;
    uses interface Clock;
}
implementation {
    /* Runs waiting tasks, at most DR_NESC_MAX_TASK_RUNS (see dr_nesc_platform.h). */
    void runTasks() {
        uint8_t runs;
        for (runs = 0; runs < DR_NESC_MAX_TASK_RUNS; runs++) {
            if (!call Scheduler.runNextTask()) {
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
}

/* MainC.nc - the boot sequence (TinyOS's MainC): the platform's entry points
 * (dr_nesc_platform.h), the scheduler and the timers' clock. */
configuration MainC {
    provides interface Boot;
}
implementation {
    components DrMainP, TinySchedulerC, TimerMilliP;

    Boot = DrMainP;
    DrMainP.Scheduler -> TinySchedulerC;
    DrMainP.Clock -> TimerMilliP;
}

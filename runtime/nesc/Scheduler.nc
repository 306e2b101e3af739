/* Scheduler.nc - the platform's side of the task scheduler. */
interface Scheduler {
    command void init();
    /* Runs the oldest posted task; FALSE when none was waiting. */
    command bool runNextTask();
}

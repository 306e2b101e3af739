/* TaskBasic.nc - how nesC's `post` and task bodies reach the scheduler
 * (-fnesc-scheduler=TinySchedulerC,TinySchedulerC.TaskBasic,TaskBasic,TaskBasic,runTask,postTask). */
interface TaskBasic {
    /* FAIL when the task is already waiting to run. */
    async command error_t postTask();
    event void runTask();
}

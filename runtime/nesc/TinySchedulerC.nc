/* TinySchedulerC.nc - first-in first-out task scheduler: every task is waiting at most once,
 * so a ring of one slot per task never overflows. */
module TinySchedulerC {
    provides interface TaskBasic[uint8_t id];
    provides interface Scheduler;
}
implementation {
    enum { N_TASKS = uniqueCount("TinySchedulerC.TaskBasic") };

    uint8_t queue[N_TASKS];
    bool waiting[N_TASKS];
    uint8_t head;
    uint8_t count;

    command void Scheduler.init() {
        uint8_t i;
        atomic {
            for (i = 0; i < N_TASKS; i++) {
                waiting[i] = FALSE;
            }
            head = 0;
            count = 0;
        }
    }

    async command error_t TaskBasic.postTask[uint8_t id]() {
        error_t result = FAIL;
        atomic {
            if (id < N_TASKS && !waiting[id]) {
                waiting[id] = TRUE;
                queue[(uint8_t)((head + count) % N_TASKS)] = id;
                count++;
                result = SUCCESS;
            }
        }
        return result;
    }

    command bool Scheduler.runNextTask() {
        uint8_t id = 0;
        bool found = FALSE;
        atomic {
            if (count > 0) {
                id = queue[head];
                head = (uint8_t)((head + 1) % N_TASKS);
                count--;
                waiting[id] = FALSE;
                found = TRUE;
            }
        }
        if (found) {
            signal TaskBasic.runTask[id]();
        }
        return found;
    }

    default event void TaskBasic.runTask[uint8_t id]() {
        (void)id;
    }
}

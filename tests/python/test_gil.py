"""Long calls release the GIL: another Python thread keeps running while the library works."""
import threading
import time

import pushpred


def test_other_threads_run_during_a_study(hex_file):
    push = pushpred.load_push(hex_file)
    ticks = []
    done = threading.Event()

    # Each tick is a time stamp taken by the counter while it holds the GIL; between ticks it waits a millisecond
    # with the GIL released. A tick stamped strictly inside the call can only exist if the call let go of the GIL.
    def count():
        while not done.is_set():
            ticks.append(time.perf_counter())
            done.wait(0.001)

    worker = threading.Thread(target=count)
    call = []

    def study():
        # The PID observer and 20 intervals make one call of about 0.1 s: the default study now takes a few
        # milliseconds, too few ticks to tell apart from a loaded machine's scheduling.
        call.append(time.perf_counter())
        pushpred.run_prediction_study(push, intervals=20, observer="pid")
        call.append(time.perf_counter())

    worker.start()
    try:
        caller = threading.Thread(target=study)
        caller.start()
        caller.join()
    finally:
        done.set()
        worker.join()
    inside = sum(1 for t in ticks if call[0] < t < call[1])
    # With the GIL held through the call, the counter could not stamp a single tick inside it.
    assert inside > 3, f"{inside} ticks in a call of {call[1] - call[0]:.3f} s"

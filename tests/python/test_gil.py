"""Long calls release the GIL: another Python thread keeps running while the library works."""
import threading

import pushpred


def test_other_threads_run_during_a_study(hex_file):
    push = pushpred.load_push(hex_file)
    ticks = []
    done = threading.Event()

    def count():
        while not done.is_set():
            ticks.append(1)
            done.wait(0.001)

    worker = threading.Thread(target=count)
    in_call = []

    def study():
        in_call.append(len(ticks))
        pushpred.run_prediction_study(push)
        in_call.append(len(ticks))

    worker.start()
    try:
        caller = threading.Thread(target=study)
        caller.start()
        caller.join()
    finally:
        done.set()
        worker.join()
    # Ticks counted while the study ran: with the GIL held through the call, the counter could not run at all.
    assert in_call[1] - in_call[0] > 3

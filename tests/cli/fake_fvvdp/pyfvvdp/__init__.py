# A stand-in for pyfvvdp (tests/cli/test_security.sh): the API run_fvvdp.py calls, returning a JOD
# computed from the frames (10 minus the mean absolute difference, in 16-bit code values / 65535),
# so the test can see that fovsim ran the script and read its results. FAKE_FVVDP_FAIL=1 makes
# predict raise, as a broken installation would.
import os


class fvvdp:
    def __init__(self, **kwargs):
        self.kwargs = kwargs

    def predict(self, test, ref, dim_order=None, frames_per_second=None, fixation_point=None):
        if os.environ.get("FAKE_FVVDP_FAIL") == "1":
            raise RuntimeError("fake pyfvvdp: asked to fail")
        d = abs(test.astype("float64") - ref.astype("float64")).mean() / 65535.0
        return 10.0 - d, None

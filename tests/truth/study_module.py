"""scripts/model-error-study.py as a module, for the checks of its modes (check_forecast_control.py,
check_identified_fused.py): they run the study's commands by hand with its own wall_args, so a check and the study
cannot disagree on the wall told."""
import importlib.util
import os


def study_module():
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts", "model-error-study.py")
    spec = importlib.util.spec_from_file_location("model_error_study", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod

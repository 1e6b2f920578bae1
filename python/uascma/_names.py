"""Names of the integer codes in uascma's records (no imports: loaded with the package)."""

# Index → name of the CMA actions (decision/cma_mdp.h, CmaAction) and of the IMM modes (telemetry.csv).
ACTION_NAMES = ("NoOp", "Terminate", "LandASAP", "LandPract")
IMM_MODE_NAMES = ("nominal",) + tuple(f"rotor{i}_out" for i in range(1, 7))

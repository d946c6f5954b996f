"""Synthetic GVT data: FRFs from modal parameters and from a flexgvt model; time data whose estimated
FRFs match the synthesised ones."""

import numpy as np

import flexgvt as fg
from flexgvt.ema import ModalModel, estimate_frf, modal_model_from_modes, synthesize_frfs, synthesize_time_data


def test_frfs_of_a_flexgvt_model_peak_at_its_modes():
    case = fg.cases.cantilever_strip(n_elements=30)
    modes = fg.solve_modes(fg.solve_static(case.model, case.configurations["unloaded"]), 4)
    tip, mid = case.references["tip_node"], case.model.node_ids[15]
    model, dofs = modal_model_from_modes(modes, [(tip, (0, 0, 1)), (mid, (0, 0, 1))])
    model = ModalModel(model.frequencies_hz, np.full(4, 0.01), model.shapes)
    f = np.linspace(0.5, 30, 6000)
    frfs = synthesize_frfs(model, f, outputs=[0, 1], inputs=[0])
    # The driving-point receptance peaks at the first bending mode; at exactly its natural
    # frequency the quadrature part is phi^2 / (2 zeta wn^2) (mass-normalised shapes).
    k = np.argmax(np.abs(frfs.H[:, 0, 0].imag))
    assert abs(f[k] - modes.frequencies_hz[0]) < 0.01
    at_fn = synthesize_frfs(model, modes.frequencies_hz[:1], outputs=[0], inputs=[0]).H[0, 0, 0]
    wn = 2 * np.pi * modes.frequencies_hz[0]
    phi = model.shapes[0, 0]
    assert abs(-at_fn.imag / (phi**2 / (2 * 0.01 * wn**2)) - 1) < 1e-3


def test_noise_level_matches_the_requested_snr():
    model = ModalModel(np.array([1.0, 5.0]), np.array([0.02, 0.05]), np.array([[1.0, 0.5], [0.3, -1.0]]))
    f = np.linspace(0.1, 10, 20000)
    clean = synthesize_frfs(model, f, [0, 1], [0])
    noisy = synthesize_frfs(model, f, [0, 1], [0], snr_db=30, seed=4, noise="uniform")
    snr = 10 * np.log10(np.mean(np.abs(clean.H) ** 2, axis=0) / np.mean(np.abs(noisy.H - clean.H) ** 2, axis=0))
    np.testing.assert_allclose(snr, 30, atol=0.2)


def test_time_data_give_back_the_synthesised_frfs():
    model = ModalModel(np.array([3.0, 11.0]), np.array([0.03, 0.02]), np.array([[1.0, 0.6], [0.4, -0.9]]))
    fs = 128.0
    t, force, resp = synthesize_time_data(model, fs, 600.0, outputs=[0, 1], inputs=[0], excitation="random", seed=1)
    est = estimate_frf(force, resp, fs, "H1", nperseg=2048)
    ref = synthesize_frfs(model, est.frequencies_hz, [0, 1], [0])
    band = (est.frequencies_hz > 1) & (est.frequencies_hz < 20)
    err = np.abs(est.H - ref.H)[band] / np.abs(ref.H)[band]
    # Zero-order hold of the force: the discrete response matches the continuous FRF up to the
    # hold's half-sample delay and random error; well below 1 % at these frequencies.
    assert np.median(err) < 0.02

"""A Python session with libbtf (docs/python.md walks through it): a real measured material from
the RGL database, a slice of it plotted with matplotlib, importance sampling checked by a
chi-square test, a generated BTF compressed and read back, and the Cornell box rendered into a
numpy array. Writes into a temporary folder (or the folder given as the first argument).

Run with Debian's python3 after `bash tools/setup/run.sh test` (or demo):
    /usr/bin/python3 docs/examples/python_session.py
Exit code 77 (skipped) when the shared data beside the checkout is absent.
"""

import os
import pathlib
import shutil
import subprocess
import sys
import tempfile

if os.environ.get("BTF_PYTHON_PATH"):  # ctest: the package of that build
    sys.path.insert(0, os.environ["BTF_PYTHON_PATH"])

import matplotlib

matplotlib.use("Agg")  # files, no window
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import btf  # noqa: E402

repo = pathlib.Path(__file__).resolve().parents[2]
shared = pathlib.Path(os.environ.get("BTF_SHARED_DATA_DIR", repo.parent / "shared" / "data" / "real"))
datagen = os.environ.get("BTF_DATAGEN") or shutil.which("btf-datagen") or str(repo / "build" / "bin" / "btf-datagen")
paper = shared / "rgl_bsdf" / "paper_white_rgb.bsdf"
if not paper.exists():
    print(f"skipped: {paper} is absent (the shared data lives beside the checkout)")
    sys.exit(77)
out = pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else pathlib.Path(tempfile.mkdtemp(prefix="btf-session-"))
out.mkdir(parents=True, exist_ok=True)

# 1. Open a measured material: the registry recognises the RGL file by its content.
paper_white = btf.open(paper)
print(paper_white.name, "- anisotropic:", paper_white.is_anisotropic)

# 2. A slice in the plane of incidence at theta_o = 45 degrees: one wo for all rows of wi is the
#    library's stream call. Negative theta_i is the mirror side (phi_i = 180).
theta_i = np.linspace(-89, 89, 357)
wi = btf.directions(theta_i)
wo = btf.direction(45)
f = paper_white.eval(wi, wo)  # (357, 3) float32, 1/sr
fig, ax = plt.subplots(figsize=(6, 3.5))
for channel, colour in enumerate("rgb"):
    ax.plot(theta_i, f[:, channel], colour, label="RGB"[channel])
ax.set(xlabel="theta_i (deg; negative: the mirror side)", ylabel="f (1/sr)", yscale="log",
       title="paper_white_rgb at theta_o = 45 deg")
ax.legend()
fig.tight_layout()
fig.savefig(out / "paper_white_slice.png", dpi=100)
print("albedo at theta_o 45:", paper_white.albedo(45))

# 3. Importance sampling: draws, their pdf (exactly pdf() of the drawn directions), and a
#    chi-square test of sample() against pdf() (200,000 draws, significance 0.01).
s = paper_white.sample(wo, btf.uniform_samples(100_000, seed=1))
assert np.array_equal(paper_white.pdf(s.wi[s.valid], wo), s.pdf[s.valid])
print(f"{s.valid.mean():.3f} of the draws returned a direction; mean weight {s.weight[s.valid].mean(axis=0)}")
chi2 = btf.chi2_test(paper_white, 45, samples=200_000, significance=0.01)
print(chi2.message)
assert chi2.accepted

# 4. A synthetic measured BTF (8 x 8 texels x 81 x 81 directions), compressed by multi-level VQ,
#    read back view by view.
subprocess.run([datagen, "btf", "--pattern", "fabric", "--size", "8", "--seed", "1", "-o", str(out / "fabric")],
               check=True, stdout=subprocess.DEVNULL)
report = btf.compress(out / "fabric", out / "fabric.btfz", epsilon=0.05)
print(f"fabric.btfz: {report['bytes']} bytes, ratio_u8 {report['ratio_u8']:.1f}, rel_rmse {report['rel_rmse']:.4f}")
compressed = btf.open_btf(out / "fabric.btfz")
view = compressed.load_view(0)  # (81 lights, 8, 8, 3)
print("view 0:", view.shape, "mean", view.mean())

# 5. The Cornell box, path traced into a numpy array (small and quick here).
subprocess.run([datagen, "scene", "cornell", "-o", str(out / "cornell")], check=True, stdout=subprocess.DEVNULL)
image = btf.render(out / "cornell" / "scene.json", spp=4, width=64, height=64)
print("render:", image.shape, image.dtype, "mean radiance", image.mean(axis=(0, 1)))
plt.imsave(out / "cornell.png", np.clip(image / (1 + image), 0, 1) ** (1 / 2.2))
print("wrote", out / "paper_white_slice.png", "and", out / "cornell.png")

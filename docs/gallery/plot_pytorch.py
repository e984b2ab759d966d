"""
PyTorch
=======

The same model code runs on PyTorch tensors (through the array API), so ``torch.autograd``
can fit a roughness by gradient descent: here σ of the full Oren–Nayar model is recovered from
samples of the model itself, starting from σ = 0.1.
"""

import matplotlib.pyplot as plt
import torch

import roughdiffuse as rd

torch.manual_seed(0)
theta = torch.rand(2, 400, dtype=torch.float64) * 1.4
phi = torch.rand(400, dtype=torch.float64) * 6.283
wi = torch.stack([torch.sin(theta[0]), torch.zeros(400, dtype=torch.float64),
                  torch.cos(theta[0])], dim=-1)
wo = torch.stack([torch.sin(theta[1]) * torch.cos(phi), torch.sin(theta[1]) * torch.sin(phi),
                  torch.cos(theta[1])], dim=-1)
target = rd.OrenNayar(albedo=0.8, sigma=0.45, variant="full").brdf(wi, wo)

sigma = torch.tensor(0.1, dtype=torch.float64, requires_grad=True)
optimiser = torch.optim.Adam([sigma], lr=0.02)
history = []
for _ in range(150):
    optimiser.zero_grad()
    loss = torch.mean((rd.OrenNayar(albedo=0.8, sigma=sigma, variant="full").brdf(wi, wo)
                       - target) ** 2)
    loss.backward()
    optimiser.step()
    history.append(sigma.item())
print(f"sigma after 150 Adam steps: {history[-1]:.4f} (truth 0.45)")

fig, ax = plt.subplots(figsize=(6, 3.2))
ax.plot(history)
ax.axhline(0.45, color="0.5", ls="--")
ax.set_xlabel("Adam step")
ax.set_ylabel("σ (rad)")
plt.show()

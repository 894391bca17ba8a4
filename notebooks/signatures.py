# %% [markdown]
# # Mode signatures and Gold codes
#
# Placeholder page (being written). Inline math $z_k = p_k \cos(2\pi f_c t_k + \theta)$ and display math
#
# $$ t(n) = 1 + 2^{\lfloor (n+2)/2 \rfloor} $$

# %%
import numpy as np
from matplotlib.figure import Figure

fig = Figure(figsize=(5, 2))
ax = fig.add_subplot()
ax.plot(np.cos(np.linspace(0, 6, 50)))
fig

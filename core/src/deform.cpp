// kcwarp: implementation pending.

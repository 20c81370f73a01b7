def fvvdp_display_geometry(resolution, fov_horizontal=None):
    return (resolution, fov_horizontal)

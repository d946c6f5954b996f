"""Mode labelling (placeholder replaced below)."""


def label_modes(modes):
    return modes

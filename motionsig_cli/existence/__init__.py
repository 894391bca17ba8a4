"""Govaers' slides: track existence by the SLRT, its studies and the schemes on a user's detections."""

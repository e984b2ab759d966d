"""V-cavity ground truth."""

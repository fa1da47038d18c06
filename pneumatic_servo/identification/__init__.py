"""Identification: predicting experiments with the model and fitting parameters to them."""

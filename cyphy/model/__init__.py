"""The elaborated model: parts, indices, constants and poses resolved."""

"""OpenUSD: stages read by OpenUSD in a confined child, as UsdPhysics describes them."""

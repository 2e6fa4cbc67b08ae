// Placeholder translation unit for a module that has no sources in a partial checkout.

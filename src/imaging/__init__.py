"""imaging: port background, radiometry, atmosphere, sensor, metrics."""

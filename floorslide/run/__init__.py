"""Running studies: execution, the result store."""

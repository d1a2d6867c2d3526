"""What every format reader shares: the reader contract, safe XML input, poses, checks."""

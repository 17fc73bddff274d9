"""Linkages after the cam (Sunkuev 1984): the structural atlas of (adjustable) chains, four-bar
function generators (the Q method, precision points, least squares, minimax), the linkage after the follower,
adjustable mechanisms and their settings."""

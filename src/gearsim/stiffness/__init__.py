"""gearsim.stiffness"""

"""Tool poses and inverse kinematics.

Poses as rigid transforms (`poses`), one pose solved within the joint limits (`solver`),
branch changes between two solutions (`branches`) and straight tool moves as dense joint
paths (`lines`). Forward kinematics is `hdselect.robot.kinematics`.
"""
